//! The datapath units the traversal calls besides the box tester: the
//! two-step instance transform, the cull-plane unit's per-ray terms
//! (`cull_ray`) and per-child test (`cull`), and the ray/triangle test.
//! [`GoldenUnits`] answers from the golden models (the renderer's default,
//! through [`crate::tester::BoxTester::units`]); `rtl::Recorder` and
//! `rtl::RtlTester` record the same calls and answer them from the RTL.
//!
//! The configurations are the renderer's: binary32 rays, round to nearest
//! even, `dot=fma`, `inverse=pre` (the scene builder stores `R⁻¹`); planes in
//! [`PLANE_FMT`] with [`PLANES_K`] shared normals; the triangle test at
//! binary32.

use crate::bvh::{PLANES_K, PLANE_FMT};
use golden_model::cull::tester::{self as cull, normal_terms_into, NormalTerm};
use golden_model::float::{FloatFormat, RoundingMode};
use golden_model::node::{NodeIn, NodeOut, Ray as NodeRay};
use golden_model::node_reorigin::{self, ReoriginParams};
use golden_model::transform::{
    self, DotStyle, InstanceTransform, InverseSource, ModelRay, WorldRay,
};
use golden_model::triangle::{self, TriIn, TriNum, TriOut};
use std::sync::LazyLock;

/// The inputs of one `cull_ray` transaction, borrowed from the traversal.
#[derive(Debug, Clone, Copy)]
pub struct RayTermsIn<'a> {
    /// model-space origin
    pub o: &'a [u64; 3],
    /// model-space direction
    pub d: &'a [u64; 3],
    /// the node's lower corner: the children's distances are measured from it
    pub r_min: &'a [u64; 3],
    /// the node's shared normals (missing ones read as 0)
    pub normals: &'a [[u64; 3]],
}

/// The inputs of one `cull` transaction, borrowed from the traversal.
#[derive(Debug, Clone, Copy)]
pub struct ChildTestIn<'a> {
    /// `≤` the segment's entry into the child's box
    pub t_lo: u64,
    /// `≥` its exit
    pub t_hi: u64,
    /// the child's distances, one per normal (missing ones read as 0)
    pub w: &'a [u64],
    /// the ray terms of the normals
    pub terms: &'a [NormalTerm],
}

/// The inputs of one `node` transaction (the node tester, re-origin design),
/// borrowed from the wide traversal.
#[derive(Debug, Clone, Copy)]
pub struct NodeTestIn<'a> {
    /// the node shape (N, q) and precision
    pub params: &'a ReoriginParams,
    /// the ray in the tree's space
    pub ray: &'a NodeRay,
    /// its direction
    pub d: &'a [u64; 3],
    /// a lower bound of every hit in the node (the parent's entry)
    pub t_start: u64,
    /// the node's frame and child integers
    pub node: &'a NodeIn,
}

/// What the traversal asks of the units other than the box tester.
pub trait Units: Sync {
    /// The world ray in the instance's model space (`transform` unit).
    fn transform(&self, ray: &WorldRay, inst: &InstanceTransform) -> ModelRay;
    /// The ray terms of a node's shared normals (`cull_ray` unit) into the
    /// first [`PLANES_K`] entries of `terms`.
    fn cull_ray(&self, x: &RayTermsIn, terms: &mut [NormalTerm]);
    /// May the segment `[t_lo, t_hi]` inside a child's box meet the child's
    /// geometry (`cull` unit; [`PLANES_K`] distances and terms)?
    fn cull(&self, x: &ChildTestIn) -> bool;
    /// The watertight ray/triangle test (`triangle` unit, `outputs=full`).
    fn triangle(&self, x: &TriIn) -> TriOut;
    /// The same test with `outputs=tnum`: `T` and `det`, no division.
    fn triangle_tnum(&self, x: &TriIn) -> TriNum;
    /// One ray against one wide node, the hit slots sorted (`node` unit).
    fn node(&self, x: &NodeTestIn) -> NodeOut;
}

/// The golden models in the renderer's configurations.
#[derive(Debug, Clone, Copy)]
pub struct GoldenUnits {
    /// the two-step transform
    pub transform: transform::Config,
    /// both cull units
    pub cull: cull::Config,
    /// the triangle test's format
    pub triangle: FloatFormat,
    /// the segment test of the `outputs=tnum` triangle unit: by logarithms,
    /// conservative (the shader re-decides `t <= t_max` after dividing)
    pub tnum_segment: triangle::Segment,
}

static GOLDEN: LazyLock<GoldenUnits> = LazyLock::new(|| GoldenUnits {
    transform: transform::Config {
        fmt: FloatFormat::BINARY32,
        mode: RoundingMode::NearestEven,
        dot: DotStyle::Fma,
        source: InverseSource::PreInverted,
    },
    cull: cull::Config::new(FloatFormat::BINARY32, PLANE_FMT, PLANES_K)
        .expect("the renderer's plane configuration is valid"),
    triangle: FloatFormat::BINARY32,
    tnum_segment: triangle::Segment::Log,
});

impl GoldenUnits {
    /// The renderer's units.
    pub fn get() -> &'static GoldenUnits {
        &GOLDEN
    }
}

impl Units for GoldenUnits {
    fn transform(&self, ray: &WorldRay, inst: &InstanceTransform) -> ModelRay {
        transform::transform(&self.transform, ray, inst)
    }
    fn cull_ray(&self, x: &RayTermsIn, terms: &mut [NormalTerm]) {
        normal_terms_into(&self.cull, x.o, x.d, x.r_min, x.normals, terms, &mut [0; 8]);
    }
    fn cull(&self, x: &ChildTestIn) -> bool {
        cull::eval_parts(&self.cull, x.t_lo, x.t_hi, x.w, x.terms).keep
    }
    fn triangle(&self, x: &TriIn) -> TriOut {
        triangle::eval(self.triangle, x)
    }
    fn triangle_tnum(&self, x: &TriIn) -> TriNum {
        triangle::eval_tnum_with(
            self.triangle,
            RoundingMode::NearestEven,
            self.tnum_segment,
            x,
        )
    }
    fn node(&self, x: &NodeTestIn) -> NodeOut {
        node_reorigin::eval(x.params, x.ray, *x.d, x.t_start, x.node)
    }
}
