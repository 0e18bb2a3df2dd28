//! Bit-accurate golden models of the units that `rtl-gen` generates.
//!
//! Written independently of the generator: nothing here calls the DSL or its
//! arithmetic. Each model computes, for one transaction, exactly the bits the
//! RTL must produce.
#![warn(missing_docs)]

pub mod cull;
pub mod exact;
pub mod float;
pub mod mulcmp;
pub mod node;
pub mod node_reorigin;
pub mod raycull;
pub mod silhouette;
pub mod slab;
pub mod transform;
pub mod triangle;
pub mod wide;
