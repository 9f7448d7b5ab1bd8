//! Clearances of the robot's collision pieces (from [`CollisionGuard`]: the same pieces, link
//! pairs and ground links as the simulation's guard) to each other, to the floor and to the
//! keep-out shapes, and how far each piece can move before a clearance may be used up.
//!
//! **Reach.** A point of a piece riding on chain frame `f` is at most
//! `R[k] = Σ |joint origins between k and f| + |piece centre in frame f| + bounding radius`
//! from revolute joint `k`'s axis (for any joint values; a prismatic joint in between adds its
//! largest travel). So when the joints move along any path, no point of the piece moves more
//! than `Σ_k R[k] · (travel of joint k)` (a prismatic joint `k` counts 1 m per m).
//!
//! **Budget.** At a checkpoint every tested pair gets its clearance `d` (the floor: the lowest
//! point of the piece's tight box; other pairs: the distance between their bounding boxes,
//! a lower bound, replaced by parry's exact distance when that bound is below
//! [`EXACT_DISTANCE_BELOW_M`]). A piece's budget is the smallest `d` over its pairs with a
//! static partner (floor, keep-out, base) and `d / 2` over pairs with another moving piece.
//! No pair can touch before one of its pieces has moved its budget.

use nalgebra::{Isometry3, Vector3};
use rapier3d::parry::bounding_volume::Aabb;
use rapier3d::parry::query;
use rapier3d::prelude::{Pose, SharedShape};

use super::problem::Problem;
use crate::collision::CollisionGuard;
use crate::collision::pose_from_iso;
use crate::model::{JointKind, RobotModel};
use crate::scene::{KeepOut, KeepOutShape};

/// Below this bounding-box distance a pair's clearance is measured exactly (parry), m. Above
/// it the box distance is close enough and costs nothing.
pub const EXACT_DISTANCE_BELOW_M: f64 = 0.04;

/// One convex piece of a link.
struct Piece {
    link: usize,
    local: Isometry3<f64>,
    shape: SharedShape,
    /// Reach from each joint's axis, m per rad (see the module docs).
    reach_m: Vec<f64>,
}

/// What a piece is tested against.
#[derive(Clone, Copy)]
enum Partner {
    Piece(usize),
    Ground,
    KeepOut(usize),
}

struct Pair {
    piece: usize,
    partner: Partner,
    problem: Problem,
    /// The partner moves too (its piece has a non-zero reach).
    partner_moves: bool,
}

struct Obstacle {
    pose: Pose,
    shape: SharedShape,
    aabb: Aabb,
}

/// The collision scene of a pre-flight checker, built once.
pub(super) struct ClearanceWorld {
    pieces: Vec<Piece>,
    pairs: Vec<Pair>,
    obstacles: Vec<Obstacle>,
    /// Per joint, the largest reach of any piece, m per rad.
    max_reach_m: Vec<f64>,
}

/// The outcome of one evaluation.
#[derive(Debug, Default)]
pub(super) struct Clearance {
    /// How far each piece may move before a pair may touch, m.
    pub budget_m: Vec<f64>,
    /// Pairs in contact now.
    pub contacts: Vec<Problem>,
    /// World pose and box of every piece.
    placed: Vec<(Pose, Aabb)>,
}

/// Largest distance from chain frame `from` (0-based joint index `from - 1`'s frame) to the
/// origin of chain frame `to` over all joint values, m (infinite past an unbounded prismatic).
fn chain_span_m(model: &RobotModel, from: usize, to: usize) -> f64 {
    // frame i (1-based) = frame i−1 · joints[i−1].origin · motion(q[i−1])
    (from + 1..=to)
        .map(|i| {
            let j = &model.joints[i - 1];
            let travel = match j.kind {
                JointKind::Prismatic => model.limits.get(i - 1).map_or(f64::INFINITY, |l| l.min.abs().max(l.max.abs())),
                _ => 0.0,
            };
            j.origin.translation.vector.norm() + travel
        })
        .sum()
}

/// Reach (m per unit of joint motion) of a point set riding on chain frame `frame` whose
/// points lie within `extent_m` of the frame's origin.
pub(super) fn reach_per_joint(model: &RobotModel, frame: usize, extent_m: f64) -> Vec<f64> {
    (0..model.dof())
        .map(|j| {
            let joint_frame = j + 1;
            if joint_frame > frame {
                0.0
            } else if model.joints[j].kind == JointKind::Prismatic {
                1.0
            } else {
                chain_span_m(model, joint_frame, frame) + extent_m
            }
        })
        .collect()
}

fn keep_out_shape(k: &KeepOut) -> (SharedShape, Isometry3<f64>) {
    let y_to_z = Isometry3::rotation(Vector3::x() * std::f64::consts::FRAC_PI_2);
    match &k.shape {
        KeepOutShape::Box { size_mm, .. } => (
            SharedShape::cuboid(
                (0.5e-3 * size_mm[0]) as f32,
                (0.5e-3 * size_mm[1]) as f32,
                (0.5e-3 * size_mm[2]) as f32,
            ),
            Isometry3::identity(),
        ),
        KeepOutShape::Sphere { radius_mm, .. } => (SharedShape::ball((1e-3 * radius_mm) as f32), Isometry3::identity()),
        KeepOutShape::Cylinder { radius_mm, height_mm, .. } => {
            (SharedShape::cylinder((0.5e-3 * height_mm) as f32, (1e-3 * radius_mm) as f32), y_to_z)
        }
    }
}

/// Distance between two boxes (0 when they overlap): a lower bound of the distance between
/// anything inside them.
fn box_distance_m(a: &Aabb, b: &Aabb) -> f64 {
    let gap = |lo_a: f32, hi_a: f32, lo_b: f32, hi_b: f32| f64::from((lo_b - hi_a).max(lo_a - hi_b).max(0.0));
    let dx = gap(a.mins.x, a.maxs.x, b.mins.x, b.maxs.x);
    let dy = gap(a.mins.y, a.maxs.y, b.mins.y, b.maxs.y);
    let dz = gap(a.mins.z, a.maxs.z, b.mins.z, b.maxs.z);
    (dx * dx + dy * dy + dz * dz).sqrt()
}

/// Clearance between two placed shapes, m (0 when they touch or overlap).
fn clearance_m(pa: &Pose, sa: &SharedShape, ba: &Aabb, pb: &Pose, sb: &SharedShape, bb: &Aabb) -> f64 {
    let bound = box_distance_m(ba, bb);
    if bound >= EXACT_DISTANCE_BELOW_M {
        return bound;
    }
    // an unsupported shape pair counts as touching (conservative)
    query::distance(pa, sa.as_ref(), pb, sb.as_ref()).map_or(0.0, |d| f64::from(d.distance).max(0.0))
}

impl ClearanceWorld {
    /// The pieces, pairs and ground links of `model`'s collision guard, plus every piece
    /// against every keep-out shape (already validated).
    pub(super) fn new(model: &RobotModel, keep_out: &[KeepOut]) -> Self {
        let guard = CollisionGuard::new(model);
        let pieces: Vec<Piece> = guard
            .pieces()
            .map(|(link, local, shape)| {
                let l = &model.links[link];
                let in_frame = l.offset * local;
                let sphere = shape.compute_local_bounding_sphere();
                let c = sphere.center();
                let centre = in_frame * nalgebra::Point3::new(f64::from(c.x), f64::from(c.y), f64::from(c.z));
                let extent_m = centre.coords.norm() + f64::from(sphere.radius());
                Piece { link, local: *local, shape: shape.clone(), reach_m: reach_per_joint(model, l.frame, extent_m) }
            })
            .collect();
        let moves = |p: usize| pieces[p].reach_m.iter().any(|&r| r > 0.0);
        let mut pairs = Vec::new();
        for &(la, lb) in guard.pair_indices() {
            for (pa, a) in pieces.iter().enumerate().filter(|(_, p)| p.link == la) {
                for (pb, _) in pieces.iter().enumerate().filter(|(_, p)| p.link == lb) {
                    pairs.push(Pair {
                        piece: pa,
                        partner: Partner::Piece(pb),
                        problem: Problem::SelfCollision(a.link, lb),
                        partner_moves: moves(pb),
                    });
                }
            }
        }
        for &l in guard.ground_link_indices() {
            for (p, _) in pieces.iter().enumerate().filter(|(_, p)| p.link == l) {
                pairs.push(Pair {
                    piece: p,
                    partner: Partner::Ground,
                    problem: Problem::Ground(l),
                    partner_moves: false,
                });
            }
        }
        let mut obstacles = Vec::new();
        for (k, ko) in keep_out.iter().enumerate() {
            let (shape, local) = keep_out_shape(ko);
            let pose = pose_from_iso(&(ko.pose_m() * local));
            let aabb = shape.compute_aabb(&pose);
            obstacles.push(Obstacle { pose, shape, aabb });
            for (p, piece) in pieces.iter().enumerate() {
                pairs.push(Pair {
                    piece: p,
                    partner: Partner::KeepOut(k),
                    problem: Problem::KeepOut(piece.link, k),
                    partner_moves: false,
                });
            }
        }
        let max_reach_m = (0..model.dof()).map(|j| pieces.iter().map(|p| p.reach_m[j]).fold(0.0, f64::max)).collect();
        Self { pieces, pairs, obstacles, max_reach_m }
    }

    /// Number of pieces (the length of [`Clearance::budget_m`]).
    pub(super) fn piece_count(&self) -> usize {
        self.pieces.len()
    }

    /// Largest reach of any piece per joint, m per rad.
    pub(super) fn max_reach_m(&self) -> &[f64] {
        &self.max_reach_m
    }

    /// True when piece `p` moves with some joint.
    pub(super) fn moves(&self, p: usize) -> bool {
        self.pieces[p].reach_m.iter().any(|&r| r > 0.0)
    }

    /// Reach of piece `p` per joint, m per rad.
    pub(super) fn reach_m(&self, p: usize) -> &[f64] {
        &self.pieces[p].reach_m
    }

    /// Clearances and budgets at link poses `link_poses` (order of the model's links).
    pub(super) fn evaluate(&self, link_poses: &[Isometry3<f64>], out: &mut Clearance) {
        out.placed.clear();
        out.placed.extend(self.pieces.iter().map(|p| {
            let w = match link_poses.get(p.link) {
                Some(l) => pose_from_iso(&(l * p.local)),
                None => Pose::IDENTITY,
            };
            (w, p.shape.compute_aabb(&w))
        }));
        out.budget_m.clear();
        out.budget_m.resize(self.pieces.len(), f64::INFINITY);
        out.contacts.clear();
        for pair in &self.pairs {
            let (pa, ba) = &out.placed[pair.piece];
            let sa = &self.pieces[pair.piece].shape;
            let (d, touching) = match pair.partner {
                Partner::Ground => {
                    let z = crate::collision::floor_height_m(ba);
                    (z.max(0.0), z < 0.0)
                }
                Partner::Piece(b) => {
                    let (pb, bb) = &out.placed[b];
                    let d = clearance_m(pa, sa, ba, pb, &self.pieces[b].shape, bb);
                    (d, d <= 0.0)
                }
                Partner::KeepOut(k) => {
                    let o = &self.obstacles[k];
                    let d = clearance_m(pa, sa, ba, &o.pose, &o.shape, &o.aabb);
                    (d, d <= 0.0)
                }
            };
            if touching && !out.contacts.contains(&pair.problem) {
                out.contacts.push(pair.problem);
            }
            let share = if pair.partner_moves { 0.5 * d } else { d };
            out.budget_m[pair.piece] = out.budget_m[pair.piece].min(share);
            if let (Partner::Piece(b), true) = (pair.partner, pair.partner_moves) {
                out.budget_m[b] = out.budget_m[b].min(share);
            }
        }
    }
}
