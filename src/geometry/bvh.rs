//! A bounding-volume hierarchy over segments for nearest-point queries whose
//! cost does not grow with the distance of the query point (a uniform grid
//! searches a square of cells as wide as that distance: the tracer's outer
//! rings, tens of millimetres from the part, spent half of mfs-sign's time
//! there).

use super::Vec2;

/// Segments per leaf.
const LEAF: usize = 4;

#[derive(Clone, Debug)]
struct Node {
    lo: Vec2,
    hi: Vec2,
    /// Leaf: the segments `order[first..first + count]`; inner node: the
    /// children's indices, `first` (left) and `count` (right).
    first: u32,
    count: u32,
    leaf: bool,
}

/// The hierarchy: nodes (root at 0) over segment indices.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

fn bounds(edges: &[(Vec2, Vec2)], ids: &[u32]) -> (Vec2, Vec2) {
    let mut lo = Vec2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for &e in ids {
        let (a, b) = edges[e as usize];
        lo = Vec2::new(lo.x.min(a.x).min(b.x), lo.y.min(a.y).min(b.y));
        hi = Vec2::new(hi.x.max(a.x).max(b.x), hi.y.max(a.y).max(b.y));
    }
    (lo, hi)
}

/// Squared distance from `p` to the box [lo, hi] (0 inside).
fn box_dist2(p: Vec2, lo: Vec2, hi: Vec2) -> f64 {
    let dx = (lo.x - p.x).max(0.0).max(p.x - hi.x);
    let dy = (lo.y - p.y).max(0.0).max(p.y - hi.y);
    dx * dx + dy * dy
}

impl Bvh {
    /// Build over the segments by median splits along the wider axis of the
    /// segment midpoints.
    pub(crate) fn new(edges: &[(Vec2, Vec2)]) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * edges.len() / LEAF + 1),
            order: (0..edges.len() as u32).collect(),
        };
        if !edges.is_empty() {
            bvh.build(edges, 0, edges.len());
        }
        bvh
    }

    /// Builds the node over `order[start..end]` and returns its index.
    fn build(&mut self, edges: &[(Vec2, Vec2)], start: usize, end: usize) -> u32 {
        let (lo, hi) = bounds(edges, &self.order[start..end]);
        let me = self.nodes.len();
        self.nodes.push(Node {
            lo,
            hi,
            first: start as u32,
            count: (end - start) as u32,
            leaf: true,
        });
        if end - start <= LEAF {
            return me as u32;
        }
        let mid_of = |e: u32| {
            let (a, b) = edges[e as usize];
            (a + b) * 0.5
        };
        let (clo, chi) = self.order[start..end].iter().fold(
            (
                Vec2::new(f64::INFINITY, f64::INFINITY),
                Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
            ),
            |(l, h), &e| {
                let m = mid_of(e);
                (
                    Vec2::new(l.x.min(m.x), l.y.min(m.y)),
                    Vec2::new(h.x.max(m.x), h.y.max(m.y)),
                )
            },
        );
        let by_x = chi.x - clo.x >= chi.y - clo.y;
        let key = |e: &u32| {
            let m = mid_of(*e);
            if by_x {
                m.x
            } else {
                m.y
            }
        };
        let half = (end - start) / 2;
        self.order[start..end].select_nth_unstable_by(half, |a, b| key(a).total_cmp(&key(b)));
        let left = self.build(edges, start, start + half);
        let right = self.build(edges, start + half, end);
        let node = &mut self.nodes[me];
        node.leaf = false;
        node.first = left;
        node.count = right;
        me as u32
    }

    /// The nearest point of the segments to `p` as (squared distance, point,
    /// segment index), or None with no segments. `hint`, the index of a segment
    /// likely to be near (the previous query's answer, for a walk along the
    /// part), only seeds the bound the search prunes with.
    pub(crate) fn nearest(
        &self,
        edges: &[(Vec2, Vec2)],
        p: Vec2,
        hint: Option<u32>,
        dist2: impl Fn(Vec2, Vec2, Vec2) -> (f64, Vec2),
    ) -> Option<(f64, Vec2, u32)> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut best = (f64::INFINITY, p, 0u32);
        if let Some(h) = hint.filter(|&h| (h as usize) < edges.len()) {
            let (a, b) = edges[h as usize];
            let (d2, q) = dist2(p, a, b);
            best = (d2, q, h);
        }
        // (node, lower bound of its squared distance). Median splits make the
        // depth at most ⌈log₂ n⌉ + 1 and the stack holds at most one node per
        // level plus one, so 64 entries cover any u32 count of segments.
        let mut stack = [(0u32, 0.0f64); 64];
        let mut top = 1;
        stack[0] = (0, box_dist2(p, self.nodes[0].lo, self.nodes[0].hi));
        while top > 0 {
            top -= 1;
            let (k, bound) = stack[top];
            if bound >= best.0 {
                continue;
            }
            let n = &self.nodes[k as usize];
            if n.leaf {
                let (s, c) = (n.first as usize, n.count as usize);
                for &e in &self.order[s..s + c] {
                    let (a, b) = edges[e as usize];
                    let (d2, q) = dist2(p, a, b);
                    if d2 < best.0 {
                        best = (d2, q, e);
                    }
                }
                continue;
            }
            let (l, r) = (n.first, n.count);
            let dl = box_dist2(p, self.nodes[l as usize].lo, self.nodes[l as usize].hi);
            let dr = box_dist2(p, self.nodes[r as usize].lo, self.nodes[r as usize].hi);
            // The nearer child is searched first (pushed last); a child that
            // cannot beat the best is not pushed at all.
            let (near, far) = if dl <= dr {
                ((l, dl), (r, dr))
            } else {
                ((r, dr), (l, dl))
            };
            if far.1 < best.0 {
                stack[top] = far;
                top += 1;
            }
            if near.1 < best.0 {
                stack[top] = near;
                top += 1;
            }
        }
        Some((best.0, best.1, best.2))
    }
    /// Whether `hit` holds for some segment whose box is within squared
    /// distance `reach2` of `p` (boxes further away are skipped; `hit` decides
    /// for each segment reached). `hint` is tried first: for a walk along the
    /// part the last answer usually decides at once.
    pub(crate) fn any_near(
        &self,
        edges: &[(Vec2, Vec2)],
        p: Vec2,
        reach2: f64,
        hint: Option<u32>,
        hit: impl Fn(Vec2, Vec2) -> bool,
    ) -> Option<u32> {
        if let Some(h) = hint.filter(|&h| (h as usize) < edges.len()) {
            let (a, b) = edges[h as usize];
            if hit(a, b) {
                return Some(h);
            }
        }
        if self.nodes.is_empty() {
            return None;
        }
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = &self.nodes[stack[top] as usize];
            if box_dist2(p, n.lo, n.hi) > reach2 {
                continue;
            }
            if n.leaf {
                let (s, c) = (n.first as usize, n.count as usize);
                for &e in &self.order[s..s + c] {
                    let (a, b) = edges[e as usize];
                    if hit(a, b) {
                        return Some(e);
                    }
                }
                continue;
            }
            stack[top] = n.count;
            stack[top + 1] = n.first;
            top += 2;
        }
        None
    }
}
