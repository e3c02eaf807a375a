//! VTK writers (work in progress this session).
