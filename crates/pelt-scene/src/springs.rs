//! Secondary motion of fur (Frantzen's "uniform vector for further dynamic displacement",
//! made per vertex): a fur material's `spring` turns each vertex's strand tip into a damped
//! spring that the skinned motion drags ([`pelt_anim::spring::Cycle`]: the clip played in a
//! loop, from its periodic state, the same offsets at a time however it was reached). The
//! tip's offset `y` (asset units) bends the comb by `y / (L c)`, with `L` the fur length and
//! `c` the vertex's comb length, so the tip moves by about `y` (less as the strand leans; the
//! strand keeps its length whatever the bend, `shell_offset` normalizes the direction); the
//! bend's part into the surface is held to 0.8, as the wind's is. The bend goes into the fur
//! vertices ([`FurVertex::bend`]), which the shells, the fur G-buffer and the fin rebuild add
//! to the combed direction (shaders/fur_common.wgsl `moving_comb`, fin_rebuild.wgsl), and
//! which the strands' roots add on the CPU ([`bent`]).
//!
//! Only meshes the GPU skins ([`crate::skin::binding`]) move under a spring: a still asset
//! keeps no spring state at all and draws exactly as without one.

use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use pelt_anim::spring::{Cycle, Spring};
use pelt_io::IoError;

use crate::asset::MeshData;
use crate::skin::SkinBinding;
use crate::vertex::FurVertex;

/// The most a bend pushes a strand into the surface (in units of the unit normal).
const MAX_INWARD: f32 = 0.8;

/// One object's springs on one clip of its skinned mesh.
#[derive(Debug, Clone)]
pub struct FurSprings {
    binding: Arc<SkinBinding>,
    clip: usize,
    cycle: Cycle,
    length: f32,
    count: usize,
}

impl FurSprings {
    /// The springs of a mesh of `count` vertices skinned by `binding`, playing clip
    /// `animation` (an unknown clip is an error naming those there are, at `doc_path`), with
    /// fur of `length` asset units.
    pub fn new(
        binding: &Arc<SkinBinding>,
        doc_path: &Path,
        animation: &str,
        spring: Spring,
        (length, count): (f32, usize),
    ) -> Result<FurSprings, IoError> {
        let clip = binding.clip(doc_path, animation)?;
        let c = &binding.rig.clips[clip];
        let cycle = Cycle::new(spring, (c.start, c.end.max(c.start)), &|t| {
            roots(binding, clip, t)
        });
        Ok(FurSprings {
            binding: Arc::clone(binding),
            clip,
            cycle,
            length,
            count,
        })
    }

    /// Whether these springs follow clip `animation`.
    pub fn plays(&self, animation: &str) -> bool {
        self.binding.rig.clips[self.clip].name == animation
    }

    /// Each vertex's bend at `t` s of the clip (xyz; zero where no range skins the vertex or
    /// it has no fur), given its fur records; w is the record's length scale, kept.
    pub fn bends(&mut self, t: f32, fur: &[FurVertex]) -> Vec<[f32; 4]> {
        let (binding, clip) = (&self.binding, self.clip);
        let offsets = self.cycle.offsets(t, &|t| roots(binding, clip, t));
        let mut out: Vec<[f32; 4]> = (0..self.count)
            .map(|i| [0.0, 0.0, 0.0, fur.get(i).map_or(1.0, |f| f.bend[3])])
            .collect();
        if offsets.iter().all(|y| *y == Vec3::ZERO) {
            return out;
        }
        let normals = posed_normals(binding, clip, t);
        let mut k = 0;
        for r in &binding.ranges {
            for v in 0..r.job.positions.len() {
                let i = r.base as usize + v;
                if let (Some(o), Some(f)) = (out.get_mut(i), fur.get(i)) {
                    let [x, y, z, _] = bend(offsets[k], normals[k], self.length * f.comb_length());
                    *o = [x, y, z, f.bend[3]];
                }
                k += 1;
            }
        }
        out
    }
}

/// The comb's bend for a tip offset `y` on a strand of length `len` with unit normal `n`.
fn bend(y: Vec3, n: Vec3, len: f32) -> [f32; 4] {
    if len.is_nan() || len <= 1e-6 || !y.is_finite() {
        return [0.0; 4];
    }
    let b = y / len;
    let bn = b.dot(n);
    (b + n * (bn.max(-MAX_INWARD) - bn)).extend(0.0).into()
}

/// Every skinned vertex's blend matrix at `t` (ranges in order), as the skinning pass forms it.
fn blends(
    binding: &SkinBinding,
    clip: usize,
    t: f32,
) -> impl Iterator<Item = (Mat4, usize, usize)> + '_ {
    let mats = binding.matrices_at(clip, t);
    binding.ranges.iter().enumerate().flat_map(move |(ri, r)| {
        let (joints, unweighted) = mats[ri].clone();
        (0..r.job.positions.len()).map(move |v| {
            let m = r.job.influences.blend(v, &joints).0.unwrap_or(unweighted);
            (m, ri, v)
        })
    })
}

/// Every skinned vertex's position at `t` s of clip `clip` (ranges in order).
fn roots(binding: &SkinBinding, clip: usize, t: f32) -> Vec<Vec3> {
    blends(binding, clip, t)
        .map(|(m, ri, v)| m.transform_point3(binding.ranges[ri].job.positions[v]))
        .collect()
}

/// Every skinned vertex's unit normal at `t` s of clip `clip` (ranges in order).
fn posed_normals(binding: &SkinBinding, clip: usize, t: f32) -> Vec<Vec3> {
    blends(binding, clip, t)
        .map(|(m, ri, v)| {
            let job = &binding.ranges[ri].job;
            let n = job.normals.as_ref().map_or(Vec3::Z, |n| n[v]);
            pelt_anim::skinning::transform(&m, job.positions[v], n, Vec4::X).1
        })
        .collect()
}

/// `mesh` with its fur vertices bent by `spring` (fur of `length` asset units) at the pose
/// it was loaded at (`SkinBinding::loaded`), for the strands' roots, which are planted on the
/// CPU (the strand reference draws no fins); `None` when nothing moves it (not skinned on the GPU, no pose, a rigid spring).
/// `path` names the asset in errors.
pub fn bent(
    mesh: &MeshData,
    spring: Spring,
    length: f32,
    path: &Path,
) -> Result<Option<MeshData>, IoError> {
    let (Some(binding), Some(fur)) = (&mesh.skin, &mesh.fur) else {
        return Ok(None);
    };
    let Some(pose) = binding.loaded.as_ref().filter(|_| !spring.rigid()) else {
        return Ok(None);
    };
    let mut springs = FurSprings::new(
        binding,
        path,
        &pose.animation,
        spring,
        (length, mesh.vertices.len()),
    )?;
    let bends = springs.bends(pose.time, &fur.vertices);
    let mut m = mesh.clone();
    if let Some(fur) = m.fur.as_mut() {
        for (v, b) in fur.vertices.iter_mut().zip(bends) {
            v.bend = b;
        }
    }
    Ok(Some(m))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bend_scales_by_the_strand_and_never_turns_it_into_the_body() {
        let n = Vec3::Z;
        let near = |a: [f32; 4], b: [f32; 4]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-6);
        let b = bend(Vec3::new(0.02, 0.0, 0.0), n, 0.04);
        assert!(near(b, [0.5, 0.0, 0.0, 0.0]), "{b:?}");
        // Pushed 3 lengths into the surface: held to 0.8 of the normal.
        let b = bend(Vec3::new(0.0, 0.01, -0.3), n, 0.1);
        assert!(near(b, [0.0, 0.1, -0.8, 0.0]), "{b:?}");
        // No fur, no bend; nothing non-finite passes.
        assert_eq!(bend(Vec3::X, n, 0.0), [0.0; 4]);
        assert_eq!(bend(Vec3::splat(f32::NAN), n, 1.0), [0.0; 4]);
    }

    #[test]
    fn a_stiff_spring_trails_its_root_by_its_acceleration_over_k() {
        use crate::asset::{PoseAt, posed, skinned};
        let path = Path::new("bent-cylinder.glb");
        let bytes = pelt_io::glb::to_vec(&pelt_fixtures::skinned::bent_cylinder()).expect("glb");
        let doc = pelt_io::load_bytes(path, bytes).expect("load");
        let at = |time: f32| PoseAt {
            animation: "Bend".into(),
            time,
        };
        let m = skinned(&doc, &at(0.0)).expect("skinned");
        let binding = m.skin.clone().expect("the cylinder skins on the GPU");
        let fur = vec![
            FurVertex {
                comb: [1.0, 0.0, 0.0, 1.0],
                ..FurVertex::NONE
            };
            m.vertices.len()
        ];
        // Critically damped and stiff (ω₀ = 100/s): settled within 0.1 s of the loop's seam,
        // then quasi-static, y = −a/k.
        let spring = Spring {
            stiffness: 1.0e4,
            damping: 200.0,
        };
        let mut s = FurSprings::new(&binding, path, "Bend", spring, (1.0, m.vertices.len()))
            .expect("springs");
        let t = 0.5;
        let b = s.bends(t, &fur);
        // The acceleration of each vertex by central differences of the CPU's own posing.
        let h = 1.0 / 64.0;
        let p = |t: f32| posed(&doc, &at(t)).expect("pose").vertices;
        let (before, now, after) = (p(t - h), p(t), p(t + h));
        let (mut worst, mut top) = (0.0f32, 0.0f32);
        for v in 0..m.vertices.len() {
            let a = (Vec3::from(after[v].position) - 2.0 * Vec3::from(now[v].position)
                + Vec3::from(before[v].position))
                / (h * h);
            let want = -a / spring.stiffness;
            let got = Vec3::from_slice(&b[v][..3]);
            worst = worst.max((got - want).length());
            top = top.max(want.length());
        }
        eprintln!("largest −a/k {top:.3e}, largest difference {worst:.3e}");
        // The bend's top swings on a circle: the tip trails toward the outside of the turn.
        assert!(top > 1.0e-4, "the clip barely moves: {top}");
        assert!(worst < 0.05 * top, "{worst} against {top}");
        // A clip the mesh does not have is an error naming those it has.
        let e = FurSprings::new(&binding, path, "Trot", spring, (1.0, 1)).expect_err("no Trot");
        assert!(e.to_string().contains("Bend"), "{e}");
    }

    use crate::scene::{Material, Scene};

    #[test]
    fn a_spring_reads_from_the_fur_material_and_bad_fields_name_their_place() {
        let parse =
            |text: &str| Scene::parse(Path::new("scene.json"), text).map_err(|e| e.to_string());
        let object = |material: &str| {
            format!("{{\"objects\": [\n{{\"asset\": \"fox.glb\", \"material\": {material}}}]}}")
        };
        let s = parse(&object(
            r#"{"kind": "fur", "spring": {"stiffness": 80, "damping": 6}}"#,
        ))
        .expect("a spring");
        let Material::Fur(f) = s.objects[0].material else {
            panic!("fur");
        };
        assert_eq!(
            f.spring,
            Some(Spring {
                stiffness: 80.0,
                damping: 6.0
            })
        );
        // Written back as read.
        let again = serde_json::to_value(s.objects[0].material).expect("json");
        assert_eq!(again["spring"]["stiffness"], 80.0);
        for (material, says) in [
            (
                r#"{"kind": "fur", "spring": {"stiffness": -1, "damping": 6}}"#,
                "stiffness must be finite and above 0",
            ),
            (
                r#"{"kind": "fur", "spring": {"stiffness": 80, "damping": 0}}"#,
                "damping must be finite and above 0",
            ),
            (
                r#"{"kind": "fur", "spring": {"stiffness": 80}}"#,
                "missing field `damping`",
            ),
            (
                r#"{"kind": "fur", "spring": {"stiffness": 80, "damping": 6, "mass": 1}}"#,
                "unknown field `mass`",
            ),
            (
                r#"{"kind": "opaque", "spring": {"stiffness": 80, "damping": 6}}"#,
                "spring",
            ),
        ] {
            let e = parse(&object(material)).expect_err(material);
            assert!(e.starts_with("scene.json:2:"), "{e}");
            assert!(e.contains(says), "{e}");
        }
    }
}
