//! Every quality knob declared once ([`KnobSpec`], one table: [`ALL`]): its name (the flag
//! of `pelt render`, `pelt view` and `pelt sweep` without dashes), the values it takes as
//! data ([`Range`]: what the flag parses, what the scene file checks, and the words errors,
//! help and reports write), its default in words, the converged reference `pelt sweep`
//! measures it against, whether it re-bakes the asset, the scene's own value and how a value
//! applies to the overrides ([`Knobs`]). The flags ([`Knobs`]' parsers), the scene file's
//! range checks, the renderer features' knob descriptors, `pelt sweep`'s table and `pelt
//! view`'s keys derive from it.

use super::range;
use super::{Knobs, ShellCount};
use crate::fur::FurData;
use crate::scene::{FurBlend, FurCoverage, FurLighting, FurSettings, Material, Scene, Technique};

pub use super::range::{Range, Reference, Value};

/// What the scene itself sets, for telling a knob's own value.
#[derive(Debug, Clone, Copy)]
pub struct Own<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The first fur asset's baked data.
    pub fur: Option<&'a FurData>,
    /// The first fur material's settings.
    pub settings: Option<FurSettings>,
}

impl<'a> Own<'a> {
    /// The scene's own settings, with its meshes' baked fur.
    pub fn of(scene: &'a Scene, meshes: &'a [crate::asset::MeshData]) -> Own<'a> {
        Own {
            scene,
            fur: meshes.iter().find_map(|m| m.fur.as_ref()),
            settings: scene.objects.iter().find_map(|o| match o.material {
                Material::Fur(f) => Some(f),
                _ => None,
            }),
        }
    }
}

/// A quality knob, declared once.
#[derive(Debug, Clone)]
pub struct KnobSpec {
    /// Its name (the flag without dashes).
    pub name: &'static str,
    /// The values it takes.
    pub range: Range,
    /// Its default, in words.
    pub default: &'static str,
    /// The converged reference `pelt sweep` measures it against.
    pub reference: Reference,
    /// Whether a new value needs the asset baked again (fur textures, comb storage).
    pub rebakes: bool,
    /// The scene's own value (None where it cannot be told).
    pub own: fn(&Own<'_>) -> Option<Value>,
    /// Applies one of its values to the overrides (None: not a scene override, the mode and
    /// the bake's settings, which `pelt sweep` applies itself).
    pub set: Option<fn(&mut Knobs, Value)>,
}

impl PartialEq for KnobSpec {
    fn eq(&self, other: &KnobSpec) -> bool {
        self.name == other.name
    }
}

impl KnobSpec {
    /// A renderer knob with no own value or setter yet (the fields below fill them).
    const fn base(name: &'static str, range: Range, default: &'static str) -> KnobSpec {
        KnobSpec {
            name,
            range,
            default,
            reference: Reference::Strands,
            rebakes: false,
            own: |_| None,
            set: None,
        }
    }

    /// One value from its flag's text (the error names the range).
    pub fn parse(&self, s: &str) -> Result<Value, String> {
        self.range.parse(s)
    }

    /// A count (a [`Range::Count`] or [`Range::PowerOfTwo`] knob's flag).
    pub fn count(&self, s: &str) -> Result<u32, String> {
        self.range.count(s)
    }

    /// A switch's flag.
    pub fn switch(&self, s: &str) -> Result<bool, String> {
        self.range.switch(s)
    }

    /// A scale's flag.
    pub fn scale(&self, s: &str) -> Result<f32, String> {
        self.range.scale(s)
    }

    /// A size's flag.
    pub fn size(&self, s: &str) -> Result<(u32, u32), String> {
        self.range.size(s)
    }

    /// A scene file's count, checked: `must be ..., got V`.
    pub fn check_count(&self, v: u32) -> Result<(), String> {
        self.range.check(Value::Count(v))
    }
}

/// Output size.
pub const SIZE: KnobSpec = KnobSpec {
    reference: Reference::Deferred,
    own: |o| Some(Value::Size(o.scene.output.width, o.scene.output.height)),
    set: Some(|k, v| {
        if let Value::Size(w, h) = v {
            k.size = Some((w, h));
        }
    }),
    ..KnobSpec::base("size", range::SIZE, "the scene's")
};

/// The renderer's mode (not a scene override: `--mode`).
pub const MODE: KnobSpec = KnobSpec {
    own: |_| Some(Value::Word("inferred")),
    ..KnobSpec::base(
        "mode",
        Range::Words(&["inferred", "deferred", "forward"]),
        "inferred",
    )
};

/// L-buffer scale.
pub const LBUFFER_SCALE: KnobSpec = KnobSpec {
    reference: Reference::Deferred,
    own: |o| Some(Value::Scale(o.scene.lbuffer_scale)),
    set: Some(|k, v| {
        if let Value::Scale(x) = v {
            k.lbuffer_scale = Some(x);
        }
    }),
    ..KnobSpec::base("lbuffer-scale", range::LBUFFER_SCALE, "the scene's (0.625)")
};

/// Discontinuity sensitive filtering.
pub const DSF: KnobSpec = KnobSpec {
    reference: Reference::Deferred,
    own: |o| Some(Value::Switch(o.scene.dsf)),
    set: Some(|k, v| k.dsf = v.on()),
    ..KnobSpec::base("dsf", Range::Switch, "on")
};

/// Shells per fur object.
pub const SHELLS: KnobSpec = KnobSpec {
    own: |o| {
        let look = &o.fur?.look;
        Some(match o.settings?.shells {
            Some(n) => Value::Count(n),
            None if look.shell_rule.is_some() => Value::Auto,
            None => Value::Count(look.shells),
        })
    },
    set: Some(|k, v| {
        k.shells = match v {
            Value::Auto => Some(ShellCount::BySize),
            v => v.count().map(ShellCount::Fixed),
        }
    }),
    ..KnobSpec::base(
        "shells",
        range::SHELLS,
        "auto: the manifest's rule, at most its count (16 from the bake)",
    )
};

/// Silhouette fins.
pub const FINS: KnobSpec = KnobSpec {
    own: |o| {
        let fins = o.settings?.fins_with(o.scene.fur_coverage);
        Some(Value::Switch(
            fins && o.fur.is_some_and(|f| !f.fins.is_empty()),
        ))
    },
    set: Some(|k, v| k.fins = v.on()),
    ..KnobSpec::base("fins", Range::Switch, "the asset's fur manifest")
};

/// How fur shells and fins are composited.
pub const FUR_BLEND: KnobSpec = KnobSpec {
    own: |o| {
        Some(Value::Word(match o.scene.fur_blend {
            FurBlend::Stipple => "stipple",
            FurBlend::Wboit => "wboit",
        }))
    },
    set: Some(|k, v| k.fur_blend = v.word()),
    ..KnobSpec::base("fur-blend", Range::Words(&["stipple", "wboit"]), "stipple")
};

/// How much of the skin each shell hides.
pub const FUR_COVERAGE: KnobSpec = KnobSpec {
    own: |o| {
        Some(Value::Word(match o.scene.fur_coverage {
            FurCoverage::Analytic => "analytic",
            FurCoverage::Binary => "binary",
        }))
    },
    set: Some(|k, v| k.fur_coverage = v.word()),
    ..KnobSpec::base(
        "fur-coverage",
        Range::Words(&["analytic", "binary"]),
        "analytic",
    )
};

/// How the deferred and inferred paths light fur.
pub const FUR_LIGHTING: KnobSpec = KnobSpec {
    own: |o| {
        Some(Value::Word(match o.scene.fur_lighting {
            FurLighting::KajiyaKay => "kajiya-kay",
            FurLighting::Revie => "revie",
        }))
    },
    set: Some(|k, v| k.fur_lighting = v.word()),
    ..KnobSpec::base(
        "fur-lighting",
        Range::Words(&["kajiya-kay", "revie"]),
        "kajiya-kay",
    )
};

/// Fur texture size (a re-bake).
pub const TEXTURE_SIZE: KnobSpec = KnobSpec {
    rebakes: true,
    own: |o| Some(Value::Count(o.fur?.model.size)),
    ..KnobSpec::base(
        "texture-size",
        Range::PowerOfTwo(16..=4096),
        "the bake config's (1024 without one)",
    )
};

/// Heightfield bits (a re-bake).
pub const HEIGHT_BITS: KnobSpec = KnobSpec {
    rebakes: true,
    own: |o| {
        Some(Value::Word(match o.fur?.model.height_bits {
            pelt_fur::HeightBits::Eight => "8",
            pelt_fur::HeightBits::Sixteen => "16",
        }))
    },
    ..KnobSpec::base("height-bits", Range::Words(&["8", "16"]), "16")
};

/// The comb's storage (a re-bake; not kept in the baked data, so no own value).
pub const QUANTIZE: KnobSpec = KnobSpec {
    rebakes: true,
    ..KnobSpec::base("quantize", Range::Words(&["u8", "u16", "float"]), "float")
};

/// Mirrors and glass: how they are drawn.
pub const REFLECTIONS: KnobSpec = KnobSpec {
    reference: Reference::RayTracer,
    own: |o| {
        Some(Value::Word(match o.scene.reflections.technique {
            Technique::DistanceMaps => "distance-maps",
            Technique::Envmap => "envmap",
            Technique::Off => "off",
        }))
    },
    set: Some(|k, v| k.reflections.technique = v.word()),
    ..KnobSpec::base(
        "reflections",
        Range::Words(&["distance-maps", "envmap", "off"]),
        "distance-maps",
    )
};

/// A count of the scene's `reflections` block: `$field` of `Reflections` and of
/// `ReflectionKnobs`.
macro_rules! reflection_count {
    ($(#[$doc:meta])* $id:ident, $name:literal, $range:expr, $default:literal, $field:ident) => {
        $(#[$doc])*
        pub const $id: KnobSpec = KnobSpec {
            reference: Reference::RayTracer,
            own: |o| Some(Value::Count(o.scene.reflections.$field)),
            set: Some(|k, v| k.reflections.$field = v.count()),
            ..KnobSpec::base($name, $range, $default)
        };
    };
}

reflection_count!(
    /// Distance-map linear search steps per quarter turn.
    LINEAR_STEPS, "linear-steps", range::LINEAR_STEPS, "32", linear_steps
);
reflection_count!(
    /// Secant refinement steps.
    SECANT_STEPS, "secant-steps", range::SECANT_STEPS, "6", secant_steps
);
reflection_count!(
    /// Distance-map layers.
    LAYERS, "layers", range::LAYERS, "3", layers
);
reflection_count!(
    /// Cube-map face size (and at most the adapter's texture limit).
    CUBE_SIZE, "cube-size", range::CUBE_SIZE, "256", cube_size
);
reflection_count!(
    /// Most specular bounces on a path.
    MAX_DEPTH, "max-depth", range::MAX_DEPTH, "4", max_depth
);

/// Min-max acceleration of the distance-map search.
pub const MIN_MAX: KnobSpec = KnobSpec {
    reference: Reference::RayTracer,
    own: |o| Some(Value::Switch(o.scene.reflections.min_max)),
    set: Some(|k, v| k.reflections.min_max = v.on()),
    ..KnobSpec::base("min-max", Range::Switch, "on")
};

/// Silhouette handling of the distance-map search.
pub const SILHOUETTES: KnobSpec = KnobSpec {
    reference: Reference::RayTracer,
    own: |o| Some(Value::Switch(o.scene.reflections.silhouettes)),
    set: Some(|k, v| k.reflections.silhouettes = v.on()),
    ..KnobSpec::base("silhouettes", Range::Switch, "on")
};

/// Shadow cube face size (the scene's `shadowMaps.size`).
pub const SHADOW_SIZE: KnobSpec = KnobSpec {
    reference: Reference::RayTracer,
    own: |o| Some(Value::Count(o.scene.shadow_maps.size)),
    set: Some(|k, v| k.shadow_size = v.count()),
    ..KnobSpec::base("shadow-size", range::SHADOW_SIZE, "the scene's (512)")
};

/// Shadow filtering: the side of the square of texels a lookup compares (`shadowMaps.pcf`).
pub const PCF: KnobSpec = KnobSpec {
    reference: Reference::RayTracer,
    own: |o| Some(Value::Count(o.scene.shadow_maps.pcf)),
    set: Some(|k, v| k.pcf = v.count()),
    ..KnobSpec::base("pcf", range::PCF, "the scene's (2)")
};

/// Deep opacity map layers (`shadowMaps.opacityLayers`).
pub const OPACITY_LAYERS: KnobSpec = KnobSpec {
    own: |o| Some(Value::Count(o.scene.shadow_maps.opacity_layers)),
    set: Some(|k, v| k.opacity_layers = v.count()),
    ..KnobSpec::base("opacity-layers", range::OPACITY_LAYERS, "the scene's (3)")
};

/// Every knob.
pub const ALL: &[&KnobSpec] = &[
    &SIZE,
    &MODE,
    &LBUFFER_SCALE,
    &DSF,
    &SHELLS,
    &FINS,
    &FUR_BLEND,
    &FUR_COVERAGE,
    &FUR_LIGHTING,
    &TEXTURE_SIZE,
    &HEIGHT_BITS,
    &QUANTIZE,
    &REFLECTIONS,
    &LINEAR_STEPS,
    &SECANT_STEPS,
    &LAYERS,
    &CUBE_SIZE,
    &MAX_DEPTH,
    &MIN_MAX,
    &SILHOUETTES,
    &SHADOW_SIZE,
    &PCF,
    &OPACITY_LAYERS,
];

/// Whether two names are the same (a `const` string comparison).
const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The knob called `name`, if any.
pub const fn find(name: &str) -> Option<&'static KnobSpec> {
    let mut i = 0;
    while i < ALL.len() {
        if same(ALL[i].name, name) {
            return Some(ALL[i]);
        }
        i += 1;
    }
    None
}

/// The knob called `name`; in a `const` (a feature's knob list) an unknown name fails the
/// build.
pub const fn named(name: &str) -> &'static KnobSpec {
    match find(name) {
        Some(k) => k,
        None => panic!("no knob spec of that name (knobs::spec::ALL)"),
    }
}

/// The scene's own value of every knob that overrides the scene, as overrides (what `pelt
/// view`'s keys start from).
pub fn own_knobs(o: &Own<'_>) -> Knobs {
    let mut k = Knobs::default();
    for spec in ALL {
        if let (Some(set), Some(v)) = (spec.set, (spec.own)(o)) {
            set(&mut k, v);
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value just past the range's end (or not in it at all), for each kind of range.
    fn outside(r: &Range) -> Vec<&'static str> {
        match r {
            Range::Count(_) | Range::AutoOrCount(_) | Range::PowerOfTwo(_) => {
                vec!["-1", "x", "1.5"]
            }
            Range::Scale(_) => vec!["0", "1.5", "NaN", "x"],
            Range::Switch => vec!["maybe", "1"],
            Range::Size(_) => vec!["0x10", "10", "10x99999"],
            Range::Words(_) => vec!["", "nope"],
        }
    }

    #[test]
    fn every_spec_is_named_once_and_found_by_its_name() {
        for (i, k) in ALL.iter().enumerate() {
            assert!(
                !ALL[..i].iter().any(|x| x.name == k.name),
                "{} twice",
                k.name
            );
            assert_eq!(find(k.name), Some(*k));
            assert_eq!(named(k.name).name, k.name);
        }
        assert_eq!(find("shell"), None);
    }

    #[test]
    fn every_range_check_takes_its_ends_and_rejects_what_lies_beyond() {
        for k in ALL {
            let r = &k.range;
            let ends: Vec<Value> = match r {
                Range::Count(x) | Range::AutoOrCount(x) | Range::PowerOfTwo(x) => {
                    vec![Value::Count(*x.start()), Value::Count(*x.end())]
                }
                Range::Scale(x) => vec![Value::Scale(*x.start()), Value::Scale(*x.end())],
                Range::Size(x) => vec![Value::Size(*x.start(), *x.end())],
                Range::Switch | Range::Words(_) => r.every().expect("a list"),
            };
            for v in ends {
                assert_eq!(r.check(v), Ok(()), "{} {v}", k.name);
                assert_eq!(k.parse(&v.to_string()), Ok(v), "{} {v}", k.name);
            }
            // Negative control: past either end, and text that is no value at all.
            let beyond: Vec<Value> = match r {
                Range::Count(x) | Range::AutoOrCount(x) | Range::PowerOfTwo(x) => {
                    let mut b = vec![Value::Count(x.end() + 1)];
                    b.extend(x.start().checked_sub(1).map(Value::Count));
                    b
                }
                Range::Scale(x) => vec![Value::Scale(x.start() / 2.0), Value::Scale(x.end() * 2.0)],
                Range::Size(x) => vec![Value::Size(x.end() + 1, *x.start())],
                Range::Switch => vec![Value::Count(1)],
                Range::Words(_) => vec![Value::Word("nope")],
            };
            for v in beyond {
                let e = r.check(v).expect_err(&format!("{} {v}", k.name));
                assert!(e.ends_with(&format!("got {v}")), "{e}");
                assert!(k.parse(&v.to_string()).is_err(), "{} {v}", k.name);
            }
            for s in outside(r) {
                let e = k.parse(s).expect_err(&format!("{} {s:?}", k.name));
                assert!(e.starts_with(&format!("{s:?} is not")), "{e}");
            }
        }
    }

    #[test]
    fn the_words_are_the_ranges() {
        assert_eq!(PCF.range.words(), "1 to 8");
        assert_eq!(SHADOW_SIZE.range.words(), "a power of two from 16 to 4096");
        assert_eq!(LBUFFER_SCALE.range.words(), "0.1 to 1");
        assert_eq!(SHELLS.range.words(), "auto (by screen size) or 1 to 256");
        assert_eq!(REFLECTIONS.range.words(), "distance-maps, envmap or off");
        assert_eq!(
            PCF.range.check(Value::Count(9)),
            Err("must be 1 to 8, got 9".into())
        );
        assert_eq!(
            SHADOW_SIZE.check_count(100),
            Err("must be a power of two from 16 to 4096, got 100".into())
        );
        assert_eq!(
            SHELLS.parse("0"),
            Err("\"0\" is not a whole number from 1 to 256, or auto".into())
        );
    }

    #[test]
    fn a_default_scene_gives_its_own_values_back_as_overrides() {
        let scene = Scene::default();
        let own = Own::of(&scene, &[]);
        let k = own_knobs(&own);
        let mut s = scene.clone();
        k.apply(&mut s);
        assert_eq!(s, scene, "the scene's own values change nothing");
        assert_eq!(
            (k.pcf, k.shadow_size, k.opacity_layers),
            (Some(2), Some(512), Some(3))
        );
        assert_eq!(k.fur_blend, Some(FurBlend::Stipple));
        assert_eq!(k.reflections.technique, Some(Technique::DistanceMaps));
        // No fur: no shells or fins to tell.
        assert_eq!((k.shells, k.fins), (None, None));
        for spec in ALL {
            let Some(v) = (spec.own)(&own) else { continue };
            assert_eq!(spec.range.check(v), Ok(()), "{} {v}", spec.name);
            if let Some(d) = spec.default.strip_prefix("the scene's (") {
                assert_eq!(format!("{v})"), d, "{}", spec.name);
            }
        }
    }
}
