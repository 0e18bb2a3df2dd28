//! Scene driver and renderer (issue #7): scenes from TOML files and OBJ meshes,
//! a two-level BVH with cull planes, traversal of rays and ray bundles through
//! the golden models of the box/bundle tester (silhouette), the cull-plane
//! tester and the two-step transform, a hybrid raster + ray-tracing renderer
//! with depth-based ray culling (seed 002), PNG output and statistics.
//! Documentation: `docs/scene.md`.
#![warn(missing_docs)]

pub mod bundle;
pub mod bvh;
pub mod cli;
pub mod hybrid;
pub mod hybrid_rtl;
pub mod mesh;
pub mod oracle;
pub mod output;
pub mod render;
pub mod rtl;
pub mod scene;
pub mod stats;
pub mod tester;
pub mod trace;
pub mod units;
pub mod wide;
pub mod wide_bundle;
