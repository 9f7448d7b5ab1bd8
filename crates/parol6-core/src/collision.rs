//! Self-collision guard: convex shapes per link, tested pairwise at a configuration or along
//! the swept path of a move, plus the ground plane (z = 0) as an obstacle.
//!
//! Skipped pairs: links on the same chain frame (rigidly joined), links on neighbouring chain
//! frames (adjacent), the model's [`RobotModel::disabled_collision_pairs`] (from an SRDF), and
//! for the embedded PAROL6 (its own primitive geometry) the pairs [`PAROL6_NEVER_COLLIDE`] (derived by sampling, see the
//! tests). Links on the root frame are not tested against the ground (they stand on it).

use nalgebra::{Isometry3, Vector3};
use rapier3d::parry::bounding_volume::{Aabb, BoundingVolume};
use rapier3d::parry::query;
use rapier3d::prelude::{Pose, Rotation, SharedShape, Vector};

use crate::model::{RobotModel, Shape};
use crate::profile::JointMove;

/// Name used for the ground plane in reports.
pub const GROUND: &str = "ground";

/// The floor rule's words for `link` (pre-flight and the manual motions say the same).
pub fn below_floor_text(link: &str) -> String {
    format!("{link} goes below the floor (z = 0)")
}

/// Height above the floor of a placed piece's lowest point, m (negative: below it). Parry's
/// boxes of convex primitives are tight, so the lowest point is exact. The one floor test of the
/// guard and of pre-flight's clearances.
pub(crate) fn floor_height_m(bb: &Aabb) -> f64 {
    f64::from(bb.mins.z)
}

/// A link below the floor plane (z = 0).
#[derive(Debug, Clone, PartialEq)]
pub struct FloorContact {
    /// The link reaching deepest.
    pub link: String,
    /// Height of its lowest point, m (negative).
    pub lowest_z_m: f64,
}

impl std::fmt::Display for FloorContact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: its lowest point at z = {:.1} mm", below_floor_text(&self.link), self.lowest_z_m * 1000.0)
    }
}

/// Floor only: the Cartesian jog of a backend with no collision model (the robot) stops before
/// the floor, as the simulation's stops before any contact.
#[derive(Debug, Clone)]
pub struct FloorGuard(pub CollisionGuard);

impl crate::motion::cartesian_jog::JogObstacleCheck for FloorGuard {
    fn contact(&self, model: &RobotModel, q: &[f64]) -> Option<(String, String)> {
        self.0.floor_contact(model, q).map(|c| (c.link, GROUND.to_string()))
    }
}

/// Link pairs of the embedded PAROL6 that cannot touch anywhere inside the joint limits,
/// found by testing every non-adjacent pair over 200 000 random in-limit configurations
/// (`derived_never_colliding_pairs_hold` re-checks them).
pub const PAROL6_NEVER_COLLIDE: &[(&str, &str)] = &[
    ("base_link", "L2"),
    ("base_link", "L3"),
    ("base_link", "L4"),
    ("L1", "L3"),
    ("L1", "L4"),
    ("L1", "L5"),
    ("L2", "L4"),
    ("L2", "L5"),
    ("L2", "L6"),
    ("L3", "L5"),
    ("L3", "L6"),
    ("L4", "L6"),
];

/// True when `model` has the embedded PAROL6's links (same geometry), so that
/// [`PAROL6_NEVER_COLLIDE`] applies. Another PAROL6 description (e.g. with meshes) does not.
pub fn is_embedded_parol6(model: &RobotModel) -> bool {
    model.is_parol6 && model.links == RobotModel::parol6().links
}

/// Largest joint step between two tested samples of a move, rad (or m).
pub const SWEEP_STEP: f64 = 0.005;

/// Two bodies in contact.
#[derive(Debug, Clone, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct CollisionReport {
    /// First link.
    pub link_a: String,
    /// Second link, or [`GROUND`].
    pub link_b: String,
}

impl std::fmt::Display for CollisionReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} collides with {}", self.link_a, self.link_b)
    }
}

/// One convex piece of a link, in the link frame.
#[derive(Clone)]
struct Piece {
    link: usize,
    local: Isometry3<f64>,
    shape: SharedShape,
}

/// Pairwise collision checks of a robot's links and the ground.
#[derive(Clone)]
pub struct CollisionGuard {
    pieces: Vec<Piece>,
    /// Pairs of link indices (into [`RobotModel::links`]) that are tested, a < b.
    pairs: Vec<(usize, usize)>,
    /// Links tested against the ground.
    ground_links: Vec<usize>,
    link_names: Vec<String>,
}

impl std::fmt::Debug for CollisionGuard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionGuard")
            .field("pieces", &self.pieces.len())
            .field("pairs", &self.pair_names())
            .field("ground_links", &self.ground_links.len())
            .finish()
    }
}

impl CollisionGuard {
    /// The guard of `model`, with the skip rules of the module docs.
    pub fn new(model: &RobotModel) -> Self {
        let mut extra: Vec<(String, String)> = model.disabled_collision_pairs.clone();
        if is_embedded_parol6(model) {
            extra.extend(PAROL6_NEVER_COLLIDE.iter().map(|(a, b)| (a.to_string(), b.to_string())));
        }
        Self::with_disabled_pairs(model, &extra)
    }

    /// The guard of `model` skipping only same-frame, adjacent and the given pairs (by link name).
    pub fn with_disabled_pairs(model: &RobotModel, disabled: &[(String, String)]) -> Self {
        let mut pieces = Vec::new();
        for (li, link) in model.links.iter().enumerate() {
            for g in &link.collisions {
                if let Some((shape, local)) = convex_shape(&g.shape) {
                    pieces.push(Piece { link: li, local: g.origin * local, shape });
                }
            }
        }
        let has_shape = |li: usize| pieces.iter().any(|p| p.link == li);
        let is_disabled = |a: &str, b: &str| disabled.iter().any(|(x, y)| (x == a && y == b) || (x == b && y == a));
        let mut pairs = Vec::new();
        for a in 0..model.links.len() {
            for b in a + 1..model.links.len() {
                let (la, lb) = (&model.links[a], &model.links[b]);
                if la.frame.abs_diff(lb.frame) <= 1 || !has_shape(a) || !has_shape(b) || is_disabled(&la.name, &lb.name)
                {
                    continue;
                }
                pairs.push((a, b));
            }
        }
        let ground_links = (0..model.links.len())
            .filter(|&l| model.links[l].frame > 0 && has_shape(l) && !is_disabled(&model.links[l].name, GROUND))
            .collect();
        Self { pieces, pairs, ground_links, link_names: model.links.iter().map(|l| l.name.clone()).collect() }
    }

    /// The tested link pairs, by name.
    pub fn pair_names(&self) -> Vec<(String, String)> {
        self.pairs.iter().map(|&(a, b)| (self.link_names[a].clone(), self.link_names[b].clone())).collect()
    }

    /// Names of the links tested against the ground.
    pub fn ground_link_names(&self) -> Vec<String> {
        self.ground_links.iter().map(|&l| self.link_names[l].clone()).collect()
    }

    /// Every convex piece: the index of its link in [`RobotModel::links`], its pose in the
    /// link frame and its shape (for distance queries beyond this guard's contact tests).
    pub fn pieces(&self) -> impl Iterator<Item = (usize, &Isometry3<f64>, &SharedShape)> + '_ {
        self.pieces.iter().map(|p| (p.link, &p.local, &p.shape))
    }

    /// The tested link pairs as indices into [`RobotModel::links`], a < b.
    pub fn pair_indices(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// Indices (into [`RobotModel::links`]) of the links tested against the ground.
    pub fn ground_link_indices(&self) -> &[usize] {
        &self.ground_links
    }

    /// World pose and bounding box of every piece at link poses `poses`.
    fn place(&self, poses: &[Isometry3<f64>]) -> Vec<Option<(Pose, Aabb)>> {
        self.pieces
            .iter()
            .map(|p| {
                let w = pose_from_iso(&(poses.get(p.link)? * p.local));
                Some((w, p.shape.compute_aabb(&w)))
            })
            .collect()
    }

    fn links_touch(&self, placed: &[Option<(Pose, Aabb)>], a: usize, b: usize) -> bool {
        for (i, pa) in self.pieces.iter().enumerate().filter(|(_, p)| p.link == a) {
            let Some((wa, ba)) = &placed[i] else { continue };
            for (j, pb) in self.pieces.iter().enumerate().filter(|(_, p)| p.link == b) {
                let Some((wb, bb)) = &placed[j] else { continue };
                // cheap box test first; the exact convex test only for overlapping boxes
                if ba.intersects(bb)
                    && query::intersection_test(wa, pa.shape.as_ref(), wb, pb.shape.as_ref())
                        .is_ok_and(|r| r.intersecting)
                {
                    return true;
                }
            }
        }
        false
    }

    fn below_ground(&self, placed: &[Option<(Pose, Aabb)>], l: usize) -> bool {
        self.lowest_z_m(placed, l).is_some_and(|z| z < 0.0)
    }

    /// Height of link `l`'s lowest point above the floor, m (`None`: no placed piece).
    fn lowest_z_m(&self, placed: &[Option<(Pose, Aabb)>], l: usize) -> Option<f64> {
        self.pieces
            .iter()
            .zip(placed)
            .filter(|(p, _)| p.link == l)
            .filter_map(|(_, placed)| placed.as_ref().map(|(_, bb)| floor_height_m(bb)))
            .reduce(f64::min)
    }

    /// The floor rule at joint values `q` (the one pre-flight applies to a program): the link
    /// reaching deepest below the floor plane (z = 0), or `None` when every tested link is above it.
    pub fn floor_contact(&self, model: &RobotModel, q: &[f64]) -> Option<FloorContact> {
        let placed = self.place(&model.link_poses(q));
        self.ground_links
            .iter()
            .filter_map(|&l| self.lowest_z_m(&placed, l).map(|z| (l, z)))
            .filter(|&(_, z)| z < 0.0)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(l, z)| FloorContact { link: self.link_names[l].clone(), lowest_z_m: z })
    }

    /// The floor rule along the straight joint-space path from `from` to `to` (a profiled joint
    /// move or a joint jog follows it): the contact at `to` when the end itself is below the
    /// floor, else the first one on the way, with its fraction of the path (0–1). Samples are
    /// spaced so no joint moves more than [`SWEEP_STEP`] between two.
    pub fn floor_on_path(&self, model: &RobotModel, from: &[f64], to: &[f64]) -> Option<(FloorContact, f64)> {
        if let Some(c) = self.floor_contact(model, to) {
            return Some((c, 1.0));
        }
        let n = from.len().min(to.len());
        let dist = (0..n).map(|k| (to[k] - from[k]).abs()).fold(0.0, f64::max);
        let samples = ((dist / SWEEP_STEP).ceil() as usize).clamp(1, 100_000);
        let mut q = to.to_vec();
        (0..samples).find_map(|i| {
            let f = i as f64 / samples as f64;
            for k in 0..n {
                q[k] = from[k] + (to[k] - from[k]) * f;
            }
            self.floor_contact(model, &q).map(|c| (c, f))
        })
    }

    /// First collision at joint values `q` (link pairs first, then the ground), or `None`.
    pub fn check(&self, model: &RobotModel, q: &[f64]) -> Option<CollisionReport> {
        let poses = model.link_poses(q);
        self.check_poses(&poses)
    }

    /// Like [`CollisionGuard::check`] from link poses (order of [`RobotModel::links`]).
    pub fn check_poses(&self, poses: &[Isometry3<f64>]) -> Option<CollisionReport> {
        let placed = self.place(poses);
        for &(a, b) in &self.pairs {
            if self.links_touch(&placed, a, b) {
                return Some(CollisionReport {
                    link_a: self.link_names[a].clone(),
                    link_b: self.link_names[b].clone(),
                });
            }
        }
        for &l in &self.ground_links {
            if self.below_ground(&placed, l) {
                return Some(CollisionReport { link_a: self.link_names[l].clone(), link_b: GROUND.to_string() });
            }
        }
        None
    }

    /// Every colliding pair at `q` (for diagnostics and tests).
    pub fn all_contacts(&self, model: &RobotModel, q: &[f64]) -> Vec<CollisionReport> {
        let placed = self.place(&model.link_poses(q));
        let mut out: Vec<CollisionReport> = self
            .pairs
            .iter()
            .filter(|&&(a, b)| self.links_touch(&placed, a, b))
            .map(|&(a, b)| CollisionReport { link_a: self.link_names[a].clone(), link_b: self.link_names[b].clone() })
            .collect();
        out.extend(
            self.ground_links
                .iter()
                .filter(|&&l| self.below_ground(&placed, l))
                .map(|&l| CollisionReport { link_a: self.link_names[l].clone(), link_b: GROUND.to_string() }),
        );
        out
    }

    /// First collision along the swept path of `mv` with the time (s from its start) at which
    /// it occurs. Samples are spaced so no joint moves more than about [`SWEEP_STEP`] between two.
    pub fn check_move(&self, model: &RobotModel, mv: &JointMove) -> Option<(CollisionReport, f64)> {
        let dist = mv.start().iter().zip(mv.goal()).map(|(a, b)| (b - a).abs()).fold(0.0, f64::max);
        // the peak speed of either profile is below twice the mean speed
        let samples = ((2.0 * dist / SWEEP_STEP).ceil() as usize).clamp(1, 1_000_000);
        let duration = mv.duration_s();
        for i in 0..=samples {
            let t = duration * i as f64 / samples as f64;
            let s = mv.sample(t);
            if let Some(c) = self.check(model, &s.q) {
                return Some((c, t));
            }
        }
        None
    }

    /// Checks the rest of a planner's current motion, from `from_s` on its clock to its end,
    /// in steps small enough that no joint moves more than the sweep step between two checks.
    /// Returns the first contact and its time after `from_s`.
    pub fn check_planned(
        &self,
        model: &RobotModel,
        planner: &crate::motion::MotionPlanner,
        from_s: f64,
    ) -> Option<(CollisionReport, f64)> {
        let end_s = planner.path_end_s().max(from_s);
        let (a, b) = (planner.path_q(from_s), planner.path_q(end_s));
        let travel = a.iter().zip(&b).map(|(x, y)| (y - x).abs()).fold(0.0, f64::max);
        // profiled moves peak below twice their mean speed
        let samples = ((2.0 * travel / SWEEP_STEP).ceil() as usize).clamp(1, 1_000_000);
        for i in 0..=samples {
            let t = from_s + (end_s - from_s) * i as f64 / samples as f64;
            if let Some(c) = self.check(model, &planner.path_q(t)) {
                return Some((c, t - from_s));
            }
        }
        None
    }

    /// First collision along a jog from `from` to `to` where each joint moves independently at
    /// `speed[k]` (rad/s) until it arrives, with the time (s) at which it occurs.
    pub fn check_jog(
        &self,
        model: &RobotModel,
        from: &[f64],
        to: &[f64],
        speed: &[f64],
    ) -> Option<(CollisionReport, f64)> {
        let n = from.len().min(to.len()).min(speed.len());
        let dist = (0..n).map(|k| (to[k] - from[k]).abs()).fold(0.0, f64::max);
        let duration = (0..n)
            .filter(|&k| speed[k] > 0.0 && speed[k].is_finite())
            .map(|k| (to[k] - from[k]).abs() / speed[k])
            .fold(0.0, f64::max);
        // every moving joint advances at most SWEEP_STEP between two samples
        let travel = (0..n)
            .filter(|&k| to[k] != from[k])
            .map(|k| if speed[k] > 0.0 && speed[k].is_finite() { speed[k] * duration } else { dist })
            .fold(0.0, f64::max);
        let samples = ((travel / SWEEP_STEP).ceil() as usize).clamp(1, 1_000_000);
        let mut q = to.to_vec();
        for i in 0..=samples {
            let t = duration * i as f64 / samples as f64;
            for k in 0..n {
                let reach = speed[k] * t;
                q[k] = from[k] + (to[k] - from[k]).clamp(-reach, reach);
            }
            if let Some(c) = self.check(model, &q) {
                return Some((c, t));
            }
        }
        None
    }
}

/// The Cartesian jog stops before the first knot this guard finds in contact.
impl crate::motion::cartesian_jog::JogObstacleCheck for CollisionGuard {
    fn contact(&self, model: &RobotModel, q: &[f64]) -> Option<(String, String)> {
        self.check(model, q).map(|c| (c.link_a, c.link_b))
    }
}

/// A rapier pose of an f64 isometry.
pub(crate) fn pose_from_iso(iso: &Isometry3<f64>) -> Pose {
    let t = iso.translation.vector;
    let r = iso.rotation;
    Pose::from_parts(
        Vector::new(t.x as f32, t.y as f32, t.z as f32),
        Rotation::from_xyzw(r.i as f32, r.j as f32, r.k as f32, r.w as f32).normalize(),
    )
}

/// Convex parry shape of a model shape, in its geometry frame. `None` for a mesh that cannot
/// be read or is degenerate. URDF cylinders and capsules run along z; parry's along y.
pub(crate) fn convex_shape(shape: &Shape) -> Option<(SharedShape, Isometry3<f64>)> {
    let y_to_z = Isometry3::rotation(Vector3::x() * std::f64::consts::FRAC_PI_2);
    let ok = |v: f64| v.is_finite() && v > 0.0;
    match shape {
        Shape::Box { size_m } => size_m.iter().all(|&s| ok(s)).then(|| {
            (
                SharedShape::cuboid(0.5 * size_m[0] as f32, 0.5 * size_m[1] as f32, 0.5 * size_m[2] as f32),
                Isometry3::identity(),
            )
        }),
        Shape::Cylinder { radius_m, length_m } => (ok(*radius_m) && ok(*length_m))
            .then(|| (SharedShape::cylinder(0.5 * *length_m as f32, *radius_m as f32), y_to_z)),
        Shape::Capsule { radius_m, length_m } => (ok(*radius_m) && length_m.is_finite() && *length_m >= 0.0)
            .then(|| (SharedShape::capsule_z(0.5 * *length_m as f32, *radius_m as f32), Isometry3::identity())),
        Shape::Sphere { radius_m } => {
            ok(*radius_m).then(|| (SharedShape::ball(*radius_m as f32), Isometry3::identity()))
        }
        Shape::Mesh { path, scale, .. } => {
            let scene = mesh_loader::Loader::default().custom_reader(crate::model::mesh_reader).load(path).ok()?;
            let points: Vec<Vector> = scene
                .meshes
                .iter()
                .flat_map(|m| m.vertices.iter())
                .map(|v| Vector::new(v[0] * scale[0] as f32, v[1] * scale[1] as f32, v[2] * scale[2] as f32))
                .collect();
            SharedShape::convex_hull(&points).map(|s| (s, Isometry3::identity()))
        }
    }
}

#[cfg(test)]
pub(crate) mod floor_tests {
    use super::*;

    /// The pose of trial 12 (n-d), Go to (90, −3.37, 180, −12.5, 28.65, 180)°, J2 at its limit.
    pub(crate) fn under_the_floor() -> Vec<f64> {
        let model = RobotModel::parol6();
        let mut q: Vec<f64> = [90.0f64, -3.37, 180.0, -12.5, 28.65, 180.0].iter().map(|d| d.to_radians()).collect();
        q[1] = q[1].min(model.limits.get(1).map_or(0.0, |l| l.max));
        q
    }

    /// Regression (trial 12 n-d): a typed pose under the floor went without a word while
    /// pre-flight refused a program step there. The manual motions' rule is pre-flight's: the
    /// same link is named, and the lowest point is given.
    #[test]
    fn the_floor_rule_names_the_link_preflight_names_and_its_depth() {
        let model = RobotModel::parol6();
        let guard = CollisionGuard::new(&model);
        let standby = crate::parol6::standby_rad();
        assert_eq!(guard.floor_contact(&model, &standby), None, "standby stands above the floor");
        let q = under_the_floor();
        let c = guard.floor_contact(&model, &q).expect("below the floor");
        assert!(c.lowest_z_m < -0.05, "{c}");
        let text = c.to_string();
        assert!(
            text.starts_with(&format!("{} goes below the floor (z = 0): its lowest point at z = -", c.link)),
            "{text}"
        );
        // the path from standby ends there: the end is reported, fraction 1
        let (on_path, at) = guard.floor_on_path(&model, &standby, &q).expect("on the path");
        assert_eq!((on_path, at), (c.clone(), 1.0));
        // a way out from under the floor to standby is above it at its end
        assert_eq!(guard.floor_contact(&model, &standby), None);
    }

    /// A straight joint path whose ends are above the floor but whose middle dips under it is
    /// caught on the way, before its end.
    #[test]
    fn a_path_dipping_under_the_floor_is_caught_on_the_way() {
        let model = RobotModel::parol6();
        let guard = CollisionGuard::new(&model);
        let q = under_the_floor();
        let standby = crate::parol6::standby_rad().to_vec();
        // from standby through the floor pose and as far again: find an end above the floor
        let beyond: Vec<f64> = standby.iter().zip(&q).map(|(a, b)| b + (b - a)).collect();
        let end = model.limits.enforce(&beyond, crate::LimitPolicy::Clamp).expect("clamped");
        if guard.floor_contact(&model, &end).is_none() {
            let (_, at) = guard.floor_on_path(&model, &standby, &end).expect("dips under");
            assert!(at > 0.0 && at < 1.0, "{at}");
        }
        assert_eq!(guard.floor_on_path(&model, &standby, &crate::parol6::park_rad()), None);
    }
}
