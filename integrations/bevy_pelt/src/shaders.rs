//! The plugin's WGSL, embedded and registered with Bevy's shader composer: pelt's own
//! `shaders/common.wgsl` and `shaders/fur_common.wgsl` (imported unchanged, as `pelt::common`
//! and `pelt::fur_common`), and the plumbing of `integrations/bevy_pelt/shaders/` that fills
//! pelt's structs from Bevy's view, mesh and lights.

use bevy::asset::uuid_handle;
use bevy::prelude::*;
use bevy::shader::Shader;

/// `pelt::common` (shaders/common.wgsl).
pub const COMMON: Handle<Shader> = uuid_handle!("b190e0ff-1212-46e0-a070-f2cae87cc07e");
/// `pelt::fur_common` (shaders/fur_common.wgsl).
pub const FUR_COMMON: Handle<Shader> = uuid_handle!("15e3aa18-b470-4533-b290-c735aaef3837");
/// `bevy_pelt::frame`.
pub const FRAME: Handle<Shader> = uuid_handle!("868d8b9c-b7d2-410b-a6ee-2a67e2537b7d");
/// `bevy_pelt::lights`.
pub const LIGHTS: Handle<Shader> = uuid_handle!("4f745e5d-b460-4198-ae7c-d7ef9ae61b85");
/// `bevy_pelt::fur_shell`: the fur's bindings, vertex stage and coverage.
pub const FUR_SHELL: Handle<Shader> = uuid_handle!("881bd276-8d47-4987-a413-9453b719fa69");
/// The fur material's prepass and shadow stages.
pub const FUR_PREPASS: Handle<Shader> = uuid_handle!("af084167-4f3a-4391-afea-47b5f5a0276a");
/// The fur material's vertex and fragment stages.
pub const FUR: Handle<Shader> = uuid_handle!("09b8ea96-c381-4dda-91b5-6ddbaa1a394a");
/// The fins' vertex and fragment stages.
pub const FINS: Handle<Shader> = uuid_handle!("98adc0ed-2e89-4e83-8e81-b15c16a7a8a7");
/// pelt's opaque surface.
pub const SURFACE: Handle<Shader> = uuid_handle!("d788ef45-3540-4e54-bb93-574bfb4a3089");
/// pelt's procedural sky.
pub const SKY: Handle<Shader> = uuid_handle!("8dde9e64-a3f1-4eb3-9ea6-4df31f4b0da0");

/// Every shader: handle, source and the path it reports in errors.
pub const SOURCES: [(Handle<Shader>, &str, &str); 10] = [
    (
        COMMON,
        include_str!("../../../shaders/common.wgsl"),
        "shaders/common.wgsl",
    ),
    (
        FUR_COMMON,
        include_str!("../../../shaders/fur_common.wgsl"),
        "shaders/fur_common.wgsl",
    ),
    (
        FRAME,
        include_str!("../shaders/frame.wgsl"),
        "integrations/bevy_pelt/shaders/frame.wgsl",
    ),
    (
        LIGHTS,
        include_str!("../shaders/lights.wgsl"),
        "integrations/bevy_pelt/shaders/lights.wgsl",
    ),
    (
        FUR_SHELL,
        include_str!("../shaders/fur_shell.wgsl"),
        "integrations/bevy_pelt/shaders/fur_shell.wgsl",
    ),
    (
        FUR,
        include_str!("../shaders/fur.wgsl"),
        "integrations/bevy_pelt/shaders/fur.wgsl",
    ),
    (
        FUR_PREPASS,
        include_str!("../shaders/fur_prepass.wgsl"),
        "integrations/bevy_pelt/shaders/fur_prepass.wgsl",
    ),
    (
        FINS,
        include_str!("../shaders/fins.wgsl"),
        "integrations/bevy_pelt/shaders/fins.wgsl",
    ),
    (
        SURFACE,
        include_str!("../shaders/surface.wgsl"),
        "integrations/bevy_pelt/shaders/surface.wgsl",
    ),
    (
        SKY,
        include_str!("../shaders/sky.wgsl"),
        "integrations/bevy_pelt/shaders/sky.wgsl",
    ),
];

/// Adds every shader to the app's `Assets<Shader>` under its fixed handle.
pub fn register(app: &mut App) {
    let mut shaders = app.world_mut().resource_mut::<Assets<Shader>>();
    for (handle, source, path) in SOURCES {
        if let Err(e) = shaders.insert(handle.id(), Shader::from_wgsl(source, path)) {
            error!("bevy_pelt: {path}: {e}");
        }
    }
}
