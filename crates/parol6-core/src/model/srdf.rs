//! SRDF: the link pairs a MoveIt configuration leaves out of self-collision checks.

use super::RobotModel;

impl RobotModel {
    /// Reads `<disable_collisions link1 link2>` pairs from SRDF text into
    /// [`Self::disabled_collision_pairs`]. Returns how many pairs were added.
    pub fn apply_srdf(&mut self, srdf: &str) -> usize {
        let mut added = 0;
        for tag in srdf.split('<').filter(|t| t.starts_with("disable_collisions")) {
            let attr = |name: &str| {
                let key = format!("{name}=\"");
                tag.find(&key).and_then(|i| {
                    let rest = &tag[i + key.len()..];
                    rest.find('"').map(|j| rest[..j].to_string())
                })
            };
            if let (Some(a), Some(b)) = (attr("link1"), attr("link2")) {
                self.disabled_collision_pairs.push((a, b));
                added += 1;
            }
        }
        added
    }
}
