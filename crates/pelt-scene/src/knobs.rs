//! The renderer's knobs as overrides of a scene (the flags of `pelt render` and the keys of
//! `pelt view`): output size, L-buffer scale, DSF, shells, fins and fur blend; and how an
//! input (a scene file or one asset framed by the default scene) becomes a scene. Each knob's
//! name, range, parse, default, own value and setter are declared once, in [`spec`]; the
//! flags here parse through it.

pub mod range;
pub mod spec;

use std::path::Path;

use crate::asset::{self, AssetError, MeshData};
#[cfg(feature = "cli")]
use crate::flags;
use crate::scene::{
    FurBlend, FurCoverage, FurLighting, Material, Reflections, Scene, SceneError, Technique,
};
use range::Value;

/// A shell count as `--shells` gives it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShellCount {
    /// By the fur's size on screen (the manifest's rule, `pelt_fur::shells`), releasing a
    /// count the scene file forces.
    BySize,
    /// This many shells.
    Fixed(u32),
}

/// `--shells`: `auto` or a count in [`range::SHELLS`]' range.
pub fn shell_count(s: &str) -> Result<ShellCount, String> {
    match range::SHELLS.parse(s)? {
        Value::Count(n) => Ok(ShellCount::Fixed(n)),
        _ => Ok(ShellCount::BySize),
    }
}

/// A fur spring, `STIFFNESS,DAMPING` (1/s² and 1/s, each finite and above 0), or `off` (an
/// infinitely stiff spring: the fur follows the skin rigidly).
pub fn spring(s: &str) -> Result<pelt_anim::spring::Spring, String> {
    if s == "off" {
        return Ok(pelt_anim::spring::Spring {
            stiffness: f32::INFINITY,
            damping: 1.0,
        });
    }
    let parsed = s
        .split_once(',')
        .and_then(|(k, d)| Some((k.trim().parse::<f32>().ok()?, d.trim().parse::<f32>().ok()?)));
    let Some((stiffness, damping)) = parsed else {
        return Err(format!(
            "{s:?} is not STIFFNESS,DAMPING (e.g. 1500,25) or off"
        ));
    };
    crate::scene::SpringSpec { stiffness, damping }.try_into()
}

/// Overrides; `None` keeps the scene's value. With the `cli` feature these are also the
/// flags of `pelt render`, `pelt view` and `pelt sweep` (clap's `Args`): each knob's flag
/// parses through its [`spec`] (the range the scene file checks), its help is written here.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct Knobs {
    /// Output size WxH (overrides the scene's; `pelt view`: the window's).
    #[cfg_attr(feature = "cli", arg(long, value_parser = |s: &str| range::SIZE.size(s)))]
    pub size: Option<(u32, u32)>,
    /// L-buffer scale, 0.1 to 1 (overrides the scene's).
    #[cfg_attr(feature = "cli", arg(long, value_parser = |s: &str| range::LBUFFER_SCALE.scale(s)))]
    pub lbuffer_scale: Option<f32>,
    /// Discontinuity sensitive filtering on or off (overrides the scene's).
    #[cfg_attr(feature = "cli", arg(long, value_name = "on|off", value_parser = |s: &str| range::SWITCH.switch(s)))]
    pub dsf: Option<bool>,
    /// Shells per fur object: 1 to 256, or auto (by the fur's size on screen, the manifest's
    /// rule, up to its count: the default); overrides the scene's and the manifest's.
    #[cfg_attr(feature = "cli", arg(long, value_name = "N|auto", value_parser = shell_count))]
    pub shells: Option<ShellCount>,
    /// Silhouette fins on or off (overrides the scene's).
    #[cfg_attr(feature = "cli", arg(long, value_name = "on|off", value_parser = |s: &str| range::SWITCH.switch(s)))]
    pub fins: Option<bool>,
    /// How fur shells and fins are composited: stipple (Revie: blended over, inner to
    /// outer) or wboit (weighted blended order-independent transparency).
    #[cfg_attr(feature = "cli", arg(long))]
    pub fur_blend: Option<FurBlend>,
    /// How much of the skin each shell hides: analytic (the strand model's optical depth
    /// where a pixel holds many strands, the heightfield where it resolves them) or binary
    /// (the heightfield alone, Revie §2.4.4 as written).
    #[cfg_attr(feature = "cli", arg(long))]
    pub fur_coverage: Option<FurCoverage>,
    /// How the deferred and inferred paths light fur: kajiya-kay (the strand tangent in
    /// the G-buffer, Kajiya-Kay per light) or revie (grain and rim-bent normals).
    #[cfg_attr(feature = "cli", arg(long))]
    pub fur_lighting: Option<FurLighting>,
    /// Mirrors and glass.
    #[cfg_attr(feature = "cli", command(flatten))]
    pub reflections: ReflectionKnobs,
    /// Shadow cube face size, a power of two from 16 to 4096 (overrides the scene's
    /// shadowMaps.size).
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| range::SHADOW_SIZE.count(s)))]
    pub shadow_size: Option<u32>,
    /// Shadow filtering: the side of the square of texels each lookup compares, 1 (hard) to 8
    /// (overrides the scene's shadowMaps.pcf).
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| range::PCF.count(s)))]
    pub pcf: Option<u32>,
    /// Deep opacity map layers through which fur shadows itself and what lies behind it, 0
    /// (none: fur casts as its base mesh) to 3 (overrides the scene's shadowMaps.opacityLayers).
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| range::OPACITY_LAYERS.count(s)))]
    pub opacity_layers: Option<u32>,
    /// Fur springs, STIFFNESS,DAMPING in 1/s² and 1/s (e.g. 1500,25), or off: every fur
    /// material's secondary motion on an animated asset (overrides the scene's).
    #[cfg_attr(feature = "cli", arg(long, value_name = "K,D|off", value_parser = spring))]
    pub spring: Option<pelt_anim::spring::Spring>,
    /// Largest texture side drawn, 1 to 16384 (default 8192): a larger image is halved until
    /// it fits while it decodes, with a warning.
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| flags::count(s, 1..=pelt_io::picture::MAX_SIDE)))]
    pub max_texture: Option<u32>,
}

/// Overrides of the scene's `reflections` block; `None` keeps the scene's value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct ReflectionKnobs {
    /// How mirrors and glass are drawn: distance-maps (GPU Gems 3 ch. 17), envmap (the
    /// classic environment-map baseline) or off (opaque).
    #[cfg_attr(
        feature = "cli",
        arg(id = "reflections", long = "reflections", value_name = "TECHNIQUE")
    )]
    pub technique: Option<Technique>,
    /// Distance-map linear search steps per quarter turn, 1 to 1024.
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| range::LINEAR_STEPS.count(s)))]
    pub linear_steps: Option<u32>,
    /// Secant refinement steps, 0 to 64.
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| range::SECANT_STEPS.count(s)))]
    pub secant_steps: Option<u32>,
    /// Distance-map layers, 3 to 8 (object front faces, back faces, and depth-peeled
    /// layers of the rest of the scene).
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| range::LAYERS.count(s)))]
    pub layers: Option<u32>,
    /// Cube-map face size, a power of two from 8 to 65536 (and at most the adapter's texture
    /// limit).
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| range::CUBE_SIZE.count(s)))]
    pub cube_size: Option<u32>,
    /// Most specular bounces on a path, 1 to 16.
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = |s: &str| range::MAX_DEPTH.count(s)))]
    pub max_depth: Option<u32>,
    /// Min-max acceleration of the distance-map search on or off.
    #[cfg_attr(feature = "cli", arg(long, value_name = "on|off", value_parser = |s: &str| range::SWITCH.switch(s)))]
    pub min_max: Option<bool>,
    /// Silhouette handling of the distance-map search on or off: unfiltered taps across two
    /// surfaces, and the surface behind a silhouette for a ray the reference point cannot
    /// follow.
    #[cfg_attr(feature = "cli", arg(long, value_name = "on|off", value_parser = |s: &str| range::SWITCH.switch(s)))]
    pub silhouettes: Option<bool>,
}

impl ReflectionKnobs {
    /// Applies the overrides to `r`.
    pub fn apply(&self, r: &mut Reflections) {
        let set = |v: &mut u32, o: Option<u32>| {
            if let Some(o) = o {
                *v = o;
            }
        };
        if let Some(t) = self.technique {
            r.technique = t;
        }
        set(&mut r.linear_steps, self.linear_steps);
        set(&mut r.secant_steps, self.secant_steps);
        set(&mut r.layers, self.layers);
        set(&mut r.cube_size, self.cube_size);
        set(&mut r.max_depth, self.max_depth);
        if let Some(m) = self.min_max {
            r.min_max = m;
        }
        if let Some(s) = self.silhouettes {
            r.silhouettes = s;
        }
    }
}

impl Knobs {
    /// How assets load under these knobs (the texture limit).
    pub fn load_options(&self) -> asset::LoadOptions {
        asset::LoadOptions {
            max_texture: self.max_texture.unwrap_or(asset::DEFAULT_MAX_TEXTURE),
        }
    }

    /// Applies the overrides to `scene`.
    pub fn apply(&self, scene: &mut Scene) {
        if let Some((w, h)) = self.size {
            scene.output.width = w;
            scene.output.height = h;
        }
        if let Some(s) = self.lbuffer_scale {
            scene.lbuffer_scale = s;
        }
        if let Some(d) = self.dsf {
            scene.dsf = d;
        }
        if let Some(b) = self.fur_blend {
            scene.fur_blend = b;
        }
        if let Some(c) = self.fur_coverage {
            scene.fur_coverage = c;
        }
        if let Some(l) = self.fur_lighting {
            scene.fur_lighting = l;
        }
        self.reflections.apply(&mut scene.reflections);
        if let Some(s) = self.shadow_size {
            scene.shadow_maps.size = s;
        }
        if let Some(p) = self.pcf {
            scene.shadow_maps.pcf = p;
        }
        if let Some(n) = self.opacity_layers {
            scene.shadow_maps.opacity_layers = n;
        }
        for o in &mut scene.objects {
            if let Material::Fur(f) = &mut o.material {
                match self.shells {
                    Some(ShellCount::BySize) => f.shells = None,
                    Some(ShellCount::Fixed(n)) => f.shells = Some(n),
                    None => {}
                }
                if let Some(on) = self.fins {
                    f.fins = Some(on);
                }
                if self.spring.is_some() {
                    f.spring = self.spring;
                }
            }
        }
    }
}

/// Why an input could not become a scene.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The scene file is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The asset could not be loaded.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// A scene object's asset could not be loaded: the scene file, the object, the asset's
    /// resolved path and why.
    #[error("{}: {source}", scene.display())]
    Object {
        /// The scene file.
        scene: std::path::PathBuf,
        /// What failed (boxed: the error stays small on the success path).
        #[source]
        source: Box<asset::ObjectAssetError>,
    },
}

/// A loaded input: the scene, its meshes and each object's mesh index.
#[derive(Debug, Clone)]
pub struct Input {
    /// The scene (overrides applied).
    pub scene: Scene,
    /// Its meshes.
    pub meshes: Vec<MeshData>,
    /// Object i's mesh is `meshes[mesh_of[i]]`.
    pub mesh_of: Vec<usize>,
}

/// Whether `path` names a scene file (`.json`) rather than an asset.
pub fn is_scene(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Loads `path`: a scene file with its assets, or one asset in the default scene
/// ([`crate::framing::asset_scene`]) at `default_size` unless `knobs.size` says otherwise.
pub fn load(path: &Path, knobs: &Knobs, default_size: (u32, u32)) -> Result<Input, InputError> {
    load_at(path, knobs, default_size, None)
}

/// [`load`] with animated assets posed at `pose`.
pub fn load_at(
    path: &Path,
    knobs: &Knobs,
    default_size: (u32, u32),
    pose: Option<&asset::PoseAt>,
) -> Result<Input, InputError> {
    let opts = knobs.load_options();
    let (mut scene, meshes, mesh_of) = if is_scene(path) {
        let scene = Scene::load(path)?;
        let (meshes, of) =
            asset::load_scene_with(&scene, pose, opts).map_err(|source| InputError::Object {
                scene: path.to_owned(),
                source: Box::new(source),
            })?;
        (scene, meshes, of)
    } else {
        let mesh = asset::load_at_with(path, pose, opts)?;
        let (w, h) = knobs.size.unwrap_or(default_size);
        let scene = crate::framing::asset_scene(path, &mesh, w, h);
        (scene, vec![mesh], vec![0])
    };
    knobs.apply(&mut scene);
    Ok(Input {
        scene,
        meshes,
        mesh_of,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{FurSettings, Object};

    #[cfg(feature = "cli")]
    #[test]
    fn the_flags_parse_into_the_overrides_and_refuse_what_a_scene_file_refuses() {
        use clap::Parser as _;
        #[derive(clap::Parser)]
        struct Cli {
            #[command(flatten)]
            knobs: Knobs,
        }
        let parse = |a: &[&str]| Cli::try_parse_from([&["pelt"], a].concat()).map(|c| c.knobs);
        let k = parse(&[
            "--dsf",
            "off",
            "--shells",
            "8",
            "--size",
            "64x32",
            "--reflections",
            "envmap",
            "--min-max",
            "on",
            "--layers",
            "4",
            "--pcf",
            "1",
            "--shadow-size",
            "1024",
            "--spring",
            "1500,25",
            "--opacity-layers",
            "0",
        ])
        .expect("valid flags");
        assert_eq!(k.dsf, Some(false));
        assert_eq!(k.shells, Some(ShellCount::Fixed(8)));
        assert_eq!(k.size, Some((64, 32)));
        assert_eq!(shell_count("auto"), Ok(ShellCount::BySize));
        assert!(shell_count("0").is_err() && shell_count("257").is_err());
        assert_eq!(k.reflections.technique, Some(Technique::Envmap));
        assert_eq!(k.reflections.min_max, Some(true));
        assert_eq!(k.reflections.layers, Some(4));
        assert_eq!((k.pcf, k.shadow_size), (Some(1), Some(1024)));
        assert_eq!(k.opacity_layers, Some(0));
        let s = k.spring.expect("a spring");
        assert_eq!((s.stiffness, s.damping), (1500.0, 25.0));
        let off = parse(&["--spring", "off"]).expect("off").spring;
        assert!(off.is_some_and(|s| s.rigid()), "{off:?}");
        assert_eq!(parse(&[]).expect("no flags"), Knobs::default());
        for bad in [
            ["--shells", "0"],
            ["--shells", "257"],
            ["--layers", "9"],
            ["--fins", "maybe"],
            ["--lbuffer-scale", "0"],
            ["--cube-size", "100"],
            ["--pcf", "9"],
            ["--opacity-layers", "4"],
            ["--shadow-size", "100"],
            ["--shadow-size", "8192"],
            ["--spring", "1500"],
            ["--spring", "0,25"],
            ["--spring", "1500,-1"],
            ["--spring", "inf,25"],
        ] {
            assert!(parse(&bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn overrides_reach_every_fur_object_and_leave_the_rest() {
        let mut s = Scene::default();
        for m in [Material::Fur(FurSettings::default()), Material::Opaque] {
            s.objects.push(Object {
                asset: "a.glb".into(),
                transform: Default::default(),
                material: m,
                color: [1.0; 3],
            });
        }
        let before = s.clone();
        Knobs::default().apply(&mut s);
        assert_eq!(s, before, "no overrides, no change");
        Knobs {
            size: Some((64, 32)),
            lbuffer_scale: Some(0.5),
            dsf: Some(false),
            shells: Some(ShellCount::Fixed(7)),
            fins: Some(false),
            fur_blend: Some(FurBlend::Wboit),
            fur_coverage: Some(FurCoverage::Binary),
            fur_lighting: Some(FurLighting::Revie),
            reflections: ReflectionKnobs {
                technique: Some(Technique::Envmap),
                linear_steps: Some(80),
                min_max: Some(false),
                ..Default::default()
            },
            shadow_size: Some(64),
            pcf: Some(3),
            opacity_layers: Some(1),
            spring: Some(pelt_anim::spring::Spring {
                stiffness: 900.0,
                damping: 12.0,
            }),
            // A load-time knob: it changes nothing in the scene.
            max_texture: Some(64),
        }
        .apply(&mut s);
        assert_eq!(
            (
                s.shadow_maps.size,
                s.shadow_maps.pcf,
                s.shadow_maps.opacity_layers
            ),
            (64, 3, 1)
        );
        assert_eq!(
            (
                s.reflections.technique,
                s.reflections.linear_steps,
                s.reflections.min_max,
                s.reflections.secant_steps
            ),
            (
                Technique::Envmap,
                80,
                false,
                Reflections::default().secant_steps
            )
        );
        assert_eq!((s.output.width, s.output.height), (64, 32));
        assert_eq!(
            (s.lbuffer_scale, s.dsf, s.fur_blend),
            (0.5, false, FurBlend::Wboit)
        );
        assert_eq!(
            (s.fur_coverage, s.fur_lighting),
            (FurCoverage::Binary, FurLighting::Revie)
        );
        let Material::Fur(f) = s.objects[0].material else {
            panic!("fur")
        };
        assert_eq!((f.shells, f.fins), (Some(7), Some(false)));
        assert_eq!(f.spring.map(|s| s.stiffness), Some(900.0));
        assert_eq!(s.objects[1].material, Material::Opaque);
    }

    #[test]
    fn an_asset_gets_the_default_scene_and_a_missing_one_is_named() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let i = load(&root.join("torus.glb"), &Knobs::default(), (120, 80)).expect("torus");
        assert_eq!((i.scene.output.width, i.scene.output.height), (120, 80));
        assert_eq!((i.meshes.len(), i.mesh_of.clone()), (1, vec![0]));
        let e = load(&root.join("no-such.glb"), &Knobs::default(), (8, 8)).expect_err("missing");
        assert!(e.to_string().contains("no-such.glb"), "{e}");
    }
}
