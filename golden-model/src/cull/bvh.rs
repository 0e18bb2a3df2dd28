//! A small binary BVH over a triangle mesh: median split on the longest
//! axis of the triangle centroids, leaves of at most `max_leaf` triangles.
//! Boxes are exact `f32` bounds of the vertices (no rounding), so they are
//! valid ray-format boxes for the testers. Nodes are stored parent before
//! children (root 0), so a reverse walk visits children first.

/// A triangle mesh in `f32` coordinates.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// vertex positions
    pub vertices: Vec<[f32; 3]>,
    /// triangles as vertex indices
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// The three corners of triangle `t`.
    pub fn corners(&self, t: u32) -> [[f32; 3]; 3] {
        self.triangles[t as usize].map(|v| self.vertices[v as usize])
    }
    /// Bounds of every vertex.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for v in &self.vertices {
            for i in 0..3 {
                lo[i] = lo[i].min(v[i]);
                hi[i] = hi[i].max(v[i]);
            }
        }
        (lo, hi)
    }
    /// `Err` naming the first vertex with a NaN or infinite coordinate (its
    /// 0-based index and coordinates). The plane builder's exact arithmetic
    /// and the box bounds need finite vertices; every mesh loader checks this.
    pub fn check_finite(&self) -> Result<(), String> {
        match self
            .vertices
            .iter()
            .position(|v| v.iter().any(|x| !x.is_finite()))
        {
            Some(i) => Err(non_finite_vertex(i, &self.vertices[i])),
            None => Ok(()),
        }
    }
}

/// The message for vertex `i` (0-based) at `v` that is not finite.
pub fn non_finite_vertex(i: usize, v: &[f32; 3]) -> String {
    format!(
        "vertex {i} (0-based) is ({}, {}, {}): coordinates must be finite (no NaN or infinity)",
        v[0], v[1], v[2]
    )
}

/// What a node holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    /// triangles `tri_order[first .. first + count]`
    Leaf {
        /// first index into [`Bvh::tri_order`]
        first: u32,
        /// number of triangles
        count: u32,
    },
    /// two children (node indices, both greater than this node's)
    Inner {
        /// first child
        left: u32,
        /// second child
        right: u32,
    },
}

/// One node: its box and contents.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    /// lower corner
    pub min: [f32; 3],
    /// upper corner
    pub max: [f32; 3],
    /// leaf or inner
    pub kind: NodeKind,
}

/// The hierarchy.
#[derive(Debug, Clone)]
pub struct Bvh {
    /// nodes, root first, every parent before its children
    pub nodes: Vec<Node>,
    /// triangle indices, grouped by leaf
    pub tri_order: Vec<u32>,
}

impl Bvh {
    /// Builds the hierarchy (`max_leaf >= 1`).
    pub fn build(mesh: &Mesh, max_leaf: usize) -> Bvh {
        let max_leaf = max_leaf.max(1);
        let mut order: Vec<u32> = (0..mesh.triangles.len() as u32).collect();
        let cent: Vec<[f32; 3]> = (0..mesh.triangles.len() as u32)
            .map(|t| {
                let c = mesh.corners(t);
                [0, 1, 2].map(|i| (c[0][i] + c[1][i] + c[2][i]) / 3.0)
            })
            .collect();
        let mut bvh = Bvh {
            nodes: Vec::new(),
            tri_order: Vec::new(),
        };
        if order.is_empty() {
            return bvh;
        }
        bvh.split(mesh, &cent, &mut order, 0, max_leaf);
        bvh.tri_order = order;
        bvh
    }

    fn split(
        &mut self,
        mesh: &Mesh,
        cent: &[[f32; 3]],
        order: &mut [u32],
        first: usize,
        max_leaf: usize,
    ) -> u32 {
        let me = self.nodes.len() as u32;
        let (lo, hi) = bounds_of(mesh, order);
        self.nodes.push(Node {
            min: lo,
            max: hi,
            kind: NodeKind::Leaf {
                first: first as u32,
                count: order.len() as u32,
            },
        });
        if order.len() <= max_leaf {
            return me;
        }
        let mut clo = [f32::INFINITY; 3];
        let mut chi = [f32::NEG_INFINITY; 3];
        for &t in order.iter() {
            for i in 0..3 {
                clo[i] = clo[i].min(cent[t as usize][i]);
                chi[i] = chi[i].max(cent[t as usize][i]);
            }
        }
        let axis = (0..3)
            .max_by(|&a, &b| (chi[a] - clo[a]).total_cmp(&(chi[b] - clo[b])))
            .unwrap();
        let mid = order.len() / 2;
        order.select_nth_unstable_by(mid, |&a, &b| {
            cent[a as usize][axis]
                .total_cmp(&cent[b as usize][axis])
                .then(a.cmp(&b))
        });
        let (l, r) = order.split_at_mut(mid);
        let left = self.split(mesh, cent, l, first, max_leaf);
        let right = self.split(mesh, cent, r, first + mid, max_leaf);
        self.nodes[me as usize].kind = NodeKind::Inner { left, right };
        me
    }

    /// The triangles of leaf `node` (empty for an inner node).
    pub fn leaf_tris(&self, node: usize) -> &[u32] {
        match self.nodes[node].kind {
            NodeKind::Leaf { first, count } => {
                &self.tri_order[first as usize..(first + count) as usize]
            }
            NodeKind::Inner { .. } => &[],
        }
    }

    /// Every triangle below `node`.
    pub fn subtree_tris(&self, node: usize) -> Vec<u32> {
        let mut out = Vec::new();
        let mut stack = vec![node];
        while let Some(n) = stack.pop() {
            match self.nodes[n].kind {
                NodeKind::Leaf { .. } => out.extend_from_slice(self.leaf_tris(n)),
                NodeKind::Inner { left, right } => {
                    stack.push(left as usize);
                    stack.push(right as usize);
                }
            }
        }
        out
    }
}

fn bounds_of(mesh: &Mesh, tris: &[u32]) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for &t in tris {
        for v in mesh.corners(t) {
            for i in 0..3 {
                lo[i] = lo[i].min(v[i]);
                hi[i] = hi[i].max(v[i]);
            }
        }
    }
    (lo, hi)
}

/// Reads a Wavefront OBJ file's `v` and `f` lines (polygons fanned into
/// triangles, negative indices and `v/t/n` forms accepted; everything else ignored).
/// A vertex with a NaN or infinite coordinate (`nan`, `inf`, or a value beyond
/// the f32 range such as `1e39`) is an error naming its line, index and coordinates.
pub fn parse_obj(text: &str) -> Result<Mesh, String> {
    let mut mesh = Mesh::default();
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f32> = it
                    .take(3)
                    .map(|s| {
                        s.parse::<f32>()
                            .map_err(|e| format!("line {}: {e}", ln + 1))
                    })
                    .collect::<Result<_, _>>()?;
                if c.len() != 3 {
                    return Err(format!("line {}: vertex needs 3 coordinates", ln + 1));
                }
                let v = [c[0], c[1], c[2]];
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(format!(
                        "line {}: {}",
                        ln + 1,
                        non_finite_vertex(mesh.vertices.len(), &v)
                    ));
                }
                mesh.vertices.push(v);
            }
            Some("f") => {
                let n = mesh.vertices.len() as i64;
                let idx: Vec<u32> = it
                    .map(|s| {
                        let i: i64 = s
                            .split('/')
                            .next()
                            .unwrap_or("")
                            .parse()
                            .map_err(|e| format!("line {}: {e}", ln + 1))?;
                        let i = if i < 0 { n + i } else { i - 1 };
                        if i < 0 || i >= n {
                            return Err(format!("line {}: vertex index out of range", ln + 1));
                        }
                        Ok(i as u32)
                    })
                    .collect::<Result<_, String>>()?;
                for j in 1..idx.len().saturating_sub(1) {
                    mesh.triangles.push([idx[0], idx[j], idx[j + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(mesh)
}
