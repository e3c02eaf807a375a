//! Mesh geometry and point location (work in progress this session).
