//! The culling oracle (issue 37, docs/node.md §11): a lower bound of what any sound culling
//! inside the node tests of the same wide tree could reach. It culls perfectly and costs
//! nothing, but it must still find the hit the image shows, so per ray at least:
//!
//! - a closest-hit ray that hits: the node tests on the TLAS path to the node holding the hit
//!   instance's leaf slot, one transform, the node tests on the BLAS path to the node holding
//!   the hit triangle's leaf slot, and every triangle of that slot (planes cull slots, not the
//!   triangles of a slot);
//! - an any-hit ray that hits: the cheapest hit of the whole scene, the shallowest TLAS leaf
//!   slot's path, one transform, the shallowest leaf slot's path of any BLAS, one triangle;
//! - a ray that hits nothing: the TLAS root's test when the traversal made it.
//!
//! Root box tests are 0 throughout. Depth is the number of node tests from a tree's root to a
//! node, both included.

use crate::bvh::Accel;
use crate::stats::KindStats;
use crate::trace::TRay;
use crate::wide::WideBvh;
use golden_model::wide::{ChildRef, MAX_CHILDREN};

/// Per primitive of one wide tree, the depth of the node holding its leaf slot and the
/// slot's primitive count (the shallowest if it is in several); the shallowest leaf slot.
#[derive(Debug, Clone, Default)]
struct Depths {
    /// indexed by primitive (triangle or instance); `(0, 0)` for one in no slot
    prim: Vec<(u32, u32)>,
    /// the least depth of a node with a leaf slot (0 for an empty tree)
    min_leaf: u32,
}

impl Depths {
    fn new(bvh: &WideBvh) -> Depths {
        let mut out = Depths::default();
        // breadth first: a parent precedes its children
        let mut depth = vec![0u32; bvh.nodes.len()];
        if let Some(d) = depth.first_mut() {
            *d = 1;
        }
        for (id, node) in bvh.nodes.iter().enumerate() {
            for i in 0..MAX_CHILDREN {
                match node.child(i) {
                    ChildRef::Inner(c) => depth[c as usize] = depth[id] + 1,
                    ChildRef::Leaf { first, count } => {
                        for &p in &bvh.prims[first as usize..(first + count) as usize] {
                            let p = p as usize;
                            if out.prim.len() <= p {
                                out.prim.resize(p + 1, (0, 0));
                            }
                            if out.prim[p].0 == 0 || depth[id] < out.prim[p].0 {
                                out.prim[p] = (depth[id], count);
                            }
                        }
                        if out.min_leaf == 0 || depth[id] < out.min_leaf {
                            out.min_leaf = depth[id];
                        }
                    }
                    ChildRef::Empty => {}
                }
            }
        }
        out
    }

    /// Depth and slot size of primitive `p`.
    fn of(&self, p: u32) -> (u32, u32) {
        let (d, n) = self.prim.get(p as usize).copied().unwrap_or((0, 0));
        assert!(d > 0, "primitive {p} is in no leaf slot of its tree");
        (d, n)
    }
}

/// The oracle's maps for one [`crate::wide::WideAccel`], built once.
#[derive(Debug, Clone, Default)]
pub struct Oracle {
    tlas: Depths,
    blas: Vec<Depths>,
    /// per instance its mesh (BLAS index)
    mesh: Vec<usize>,
    /// the least depth of a leaf slot's node over every non-empty BLAS
    min_blas_leaf: u32,
}

impl Oracle {
    /// The maps of the trees `tlas` and `blas` (one per mesh) of `accel`.
    pub fn new(accel: &Accel, tlas: &WideBvh, blas: &[WideBvh]) -> Oracle {
        let blas: Vec<Depths> = blas.iter().map(Depths::new).collect();
        let min_blas_leaf = blas
            .iter()
            .map(|d| d.min_leaf)
            .filter(|&d| d > 0)
            .min()
            .unwrap_or(0);
        Oracle {
            tlas: Depths::new(tlas),
            blas,
            mesh: accel.instances.iter().map(|x| x.mesh).collect(),
            min_blas_leaf,
        }
    }

    /// Counts into `st` what the oracle spends on the traced ray `r`; `tlas_root_tested`:
    /// the traversal tested the TLAS root node.
    pub fn count(&self, r: &TRay, tlas_root_tested: bool, st: &mut KindStats) {
        let (tlas, transforms, blas, tris) = if !r.hit.is_hit() {
            (u32::from(tlas_root_tested), 0, 0, 0)
        } else if r.any {
            (self.tlas.min_leaf, 1, self.min_blas_leaf, 1)
        } else {
            let (tlas, _) = self.tlas.of(r.hit.inst);
            let (blas, tris) = self.blas[self.mesh[r.hit.inst as usize]].of(r.hit.prim);
            (tlas, 1, blas, tris)
        };
        st.oracle_tlas_node_tests += u64::from(tlas);
        st.oracle_transforms += transforms;
        st.oracle_blas_node_tests += u64::from(blas);
        st.oracle_tri_tests += u64::from(tris);
    }
}
