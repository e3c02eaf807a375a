//! LIGGGHTS dump reading (work in progress this session).
