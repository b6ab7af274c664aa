//! The scene a plan runs: the scene with its vehicle moving along a profile (its prescribed
//! motion) until the end of the run, as a value or as a scene file.

use crate::Result;
use telescopic_runtime::{Profile, Scene, SceneFile};

/// The file of `scene` moving along `profile` (its prescribed motion) until `end` (s): what
/// a plan writes, and the scene its runs patch with each plant's values.
pub fn moving_file(scene: &Scene, profile: &Profile, end: f64) -> SceneFile {
    let mut file = scene.file.clone();
    file.drive.force = None;
    file.drive.motion = Some(profile.clone());
    file.time.end = end;
    file
}

/// The scene moving along `profile` (its prescribed motion) until `end` (s).
///
/// # Errors
/// [`crate::Error::Scene`] when the profile breaks a scene rule.
pub fn moving_scene(scene: &Scene, profile: &Profile, end: f64) -> Result<Scene> {
    Ok(Scene::from_file(
        moving_file(scene, profile, end),
        &scene.name,
    )?)
}
