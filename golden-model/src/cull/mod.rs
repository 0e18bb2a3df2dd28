//! Cull planes (seed 001, issues #6, #13): per BVH node, up to K planes that mark
//! empty parts of the node's box. The specification, with the proofs that
//! every rounding only makes culling less likely, is `docs/cull.md`.
//!
//! * [`tester`]: the bit-accurate tester (box interval folded with the planes);
//! * [`exact`]: the exact reference (dyadic big-integer arithmetic);
//! * [`bvh`]: a small median-split BVH and an OBJ reader;
//! * [`builder`]: the software builder that places and quantises the planes;
//! * [`stats`]: traversal counts with and without planes.

pub mod builder;
pub mod bvh;
pub mod exact;
pub mod stats;
pub mod tester;

pub use tester::{
    eval, eval_generic, eval_parts, eval_trace, normal_terms, normal_terms_generic,
    normal_terms_into, ray_terms, ray_terms_parts, ChildIn, Config, CullOut, RayIn, RayTerms,
};
