//! What a checkerboard renderer runs for a scene, decided before anything is created: passes,
//! targets and reconstruction inputs the scene does not need are left out.

use serde::Serialize;

use super::sampling::CheckerboardPath;
use super::scene::CheckerboardScene;

/// Forward: the scene shaded straight into the checkerboard targets. Deferred: a checkerboard
/// G-buffer, each sample shaded into the shade resolve target, transparents into a separate
/// checkerboard forward buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shading {
    Forward,
    Deferred,
}

impl Shading {
    pub const ALL: [Self; 2] = [Self::Forward, Self::Deferred];

    pub fn parse(name: &str) -> anyhow::Result<Self> {
        Self::ALL
            .into_iter()
            .find(|s| s.name() == name)
            .ok_or_else(|| anyhow::anyhow!("unknown shading {name:?}; expected forward or deferred"))
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Forward => "forward",
            Self::Deferred => "deferred",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct CheckerboardPlan {
    pub path: CheckerboardPath,
    pub shading: Shading,
    /// Per-object motion vectors: only where some object moves.
    pub object_motion: bool,
    /// Camera reprojection from depth in the reconstruction: only where the camera moves.
    pub camera_reprojection: bool,
    /// Transparent draws: forward into the frame, or into the deferred path's forward buffer.
    pub transparents: bool,
    /// The deferred path's checkerboard forward buffer: only with transparent draws.
    pub forward_buffer: bool,
}

impl CheckerboardPlan {
    pub fn new(scene: &CheckerboardScene, path: CheckerboardPath, shading: Shading) -> Self {
        let transparents = scene.has_transparents();
        Self {
            path,
            shading,
            object_motion: scene.objects_move(),
            camera_reprojection: scene.camera_moves(),
            transparents,
            forward_buffer: shading == Shading::Deferred && transparents,
        }
    }

    /// The passes one frame runs, in order (`history`: frame N−1 exists).
    pub fn passes(&self) -> Vec<&'static str> {
        let msaa = self.path == CheckerboardPath::Msaa2x;
        let mut passes = Vec::new();
        match self.shading {
            Shading::Forward => {
                passes.push("scene forward");
                if msaa {
                    passes.extend(["unpack colour", "unpack depth"]);
                }
            }
            Shading::Deferred => {
                passes.push("gbuffer");
                if self.forward_buffer {
                    passes.push("forward buffer");
                    if msaa {
                        passes.push("unpack forward buffer");
                    }
                }
                passes.push("shade samples");
                if msaa {
                    passes.push("unpack depth");
                }
            }
        }
        if self.object_motion {
            passes.push("object motion");
            if msaa {
                passes.push("unpack motion");
            }
        }
        passes.push("reconstruction");
        passes
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    #[test]
    fn shadings_parse_back_from_their_names() {
        assert_eq!(Shading::ALL.map(Shading::name), ["forward", "deferred"]);
        for shading in Shading::ALL {
            assert_eq!(Shading::parse(shading.name()).unwrap(), shading);
        }
        assert!(Shading::parse("Forward").is_err());
    }

    use super::*;
    use crate::cbr::scene::{Motion, flat_rects, textured_corridor};

    #[test]
    fn a_static_opaque_scene_needs_no_motion_and_no_forward_buffer() {
        let plan = CheckerboardPlan::new(
            &flat_rects((16, 16), 1, Vec2::ZERO),
            CheckerboardPath::OffsetPasses,
            Shading::Deferred,
        );
        assert!(!plan.object_motion && !plan.camera_reprojection && !plan.forward_buffer && !plan.transparents);
        assert_eq!(plan.passes(), ["gbuffer", "shade samples", "reconstruction"]);
    }

    #[test]
    fn only_what_moves_or_is_transparent_adds_passes() {
        let panning = textured_corridor(1, 1, Motion::Pan(Vec2::new(1.0, 0.0)));
        let plan = CheckerboardPlan::new(&panning, CheckerboardPath::OffsetPasses, Shading::Forward);
        // The camera's motion comes from depth in the reconstruction: no motion pass.
        assert!(plan.camera_reprojection && !plan.object_motion && !plan.forward_buffer);
        assert_eq!(plan.passes(), ["scene forward", "reconstruction"]);

        let moving = textured_corridor(1, 1, Motion::Object(0.1));
        let plan = CheckerboardPlan::new(&moving, CheckerboardPath::Msaa2x, Shading::Deferred);
        assert!(!plan.camera_reprojection && plan.object_motion && plan.forward_buffer);
        assert_eq!(
            plan.passes(),
            [
                "gbuffer",
                "forward buffer",
                "unpack forward buffer",
                "shade samples",
                "unpack depth",
                "object motion",
                "unpack motion",
                "reconstruction"
            ]
        );
    }
}
