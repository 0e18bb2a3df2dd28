//! Hybrid raster + ray tracing (seed 002).
