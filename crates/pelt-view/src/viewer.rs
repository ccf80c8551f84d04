//! The state of `pelt view` apart from the window system: the open input (last good scene),
//! the orbit camera, the settings the keys turn, the frame budget, and drawing one frame into
//! a surface texture: at full quality when the camera is still, or, while it moves, at the
//! quality the budget picks (lower L-buffer scale and shells, and a reduced resolution scaled
//! up to the window). In strands mode a still camera refines the explicit strands
//! progressively (`pelt_preview::progressive`): one more jittered sample every frame, the
//! running mean shown, restarted by any change of camera, settings, size, input or pose.

use std::path::{Path, PathBuf};
use std::time::Instant;

use pelt_preview::Pass;
use pelt_preview::animate::{self, Followed};
use pelt_preview::budget::{Budget, Costs, Quality};
use pelt_preview::features::Output;
use pelt_preview::features::registry::builder;
use pelt_preview::features::upscale::Upscale;
use pelt_preview::knobs::{self, Input, Knobs, ShellCount};
use pelt_preview::orbit::Orbit;
use pelt_preview::progressive::Progressive;
use pelt_preview::scene::{Material, Scene};
use pelt_preview::{Image, Preview, RenderError, SceneView, ViewOutput};

use crate::controls::Settings;
use crate::timeline::{Timeline, UnknownClip};
use crate::watch::Watch;

/// The window's output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Surface {
    /// Size in pixels.
    pub size: (u32, u32),
    /// Format.
    pub format: wgpu::TextureFormat,
}

/// A reduced-resolution view and its upscale into the window.
#[derive(Debug)]
struct Reduced {
    view: SceneView,
    upscale: Upscale,
}

/// Samples per pixel after which strands mode stops refining (the strand reference
/// converges to about FLIP 0.004 half-vs-half by 2048).
pub const MAX_REFINE: u32 = 4096;

/// Strands mode's progressive refinement: its own view (rendered to a texture and read
/// back), the running mean and the scene it belongs to.
#[derive(Debug)]
struct Refining {
    view: SceneView,
    mean: Progressive,
    scene: Scene,
    /// When this mean started (its estimate of the time left).
    since: Instant,
}

/// The strands mode's status: the samples so far of [`MAX_REFINE`], a bar, and the time
/// left at the rate so far (`elapsed`: seconds since the mean started).
pub fn refine_status(samples: u32, elapsed: f64) -> String {
    if samples >= MAX_REFINE {
        return format!(", explicit strands, {samples} samples (done)");
    }
    if samples == 0 {
        return ", explicit strands, starting".to_owned();
    }
    const BAR: usize = 16;
    let filled = (samples as usize * BAR) / MAX_REFINE as usize;
    let left = elapsed / f64::from(samples) * f64::from(MAX_REFINE - samples);
    let left = if left < 90.0 {
        format!("{left:.0} s")
    } else {
        format!("{:.0} min", left / 60.0)
    };
    format!(
        ", explicit strands, {samples} of {MAX_REFINE} samples [{}{}], about {left} left (refining while still)",
        "#".repeat(filled),
        "-".repeat(BAR - filled)
    )
}

/// Everything `pelt view` draws.
#[derive(Debug)]
pub struct Viewer {
    /// The input path.
    pub path: PathBuf,
    /// The last input that loaded (knobs not applied).
    pub input: Input,
    /// The mode and knob overrides.
    pub settings: Settings,
    /// The camera.
    pub orbit: Orbit,
    /// Whether the camera left the scene's own (so `orbit` decides it).
    pub moved: bool,
    /// The frame budget, once measured.
    pub budget: Option<Budget>,
    /// Target frame time while moving.
    pub target_ms: f64,
    /// Last measured pass times of the full-quality frame, for the overlay.
    pub pass_ms: Vec<(Pass, f64)>,
    /// The quality of the last frame drawn.
    pub last_quality: Option<Quality>,
    /// The animation playing, when the input is an animated asset.
    pub timeline: Option<Timeline>,
    /// The scene's clock, when its wind stirs the fur and no animation keeps the time.
    pub clock: Option<WindClock>,
    /// The animated asset's document (posed afresh for each time drawn).
    animated: Option<pelt_io::Document>,
    /// The pose the meshes were last built at.
    posed_at: Option<pelt_preview::asset::PoseAt>,
    /// The pose the GPU skinned the views to since the input was loaded (None: the loaded
    /// pose). Poses belong to each view's objects, so a view prepared later is posed to it.
    gpu_pose: Option<pelt_preview::asset::PoseAt>,
    full: SceneView,
    reduced: Option<Reduced>,
    refining: Option<Refining>,
    surface: Surface,
    watch: Watch,
}

/// The clock of a scene with wind and no animation: where the wind is evaluated, and whether
/// it advances (Space plays and pauses it, `,` `.` step a frame), as an animation's timeline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindClock {
    /// Seconds into the scene.
    pub time: f32,
    /// Whether time advances.
    pub playing: bool,
}

impl WindClock {
    /// The status line.
    pub fn status(&self) -> String {
        format!(
            "wind {:.2} s {}",
            self.time,
            if self.playing { "playing" } else { "paused" }
        )
    }
}

/// An animated asset's document and timeline (None for scene files and static assets).
fn animation_of(
    path: &Path,
    start: Option<&str>,
    time: f32,
    playing: bool,
) -> Result<Option<(pelt_io::Document, Timeline)>, ViewError> {
    if knobs::is_scene(path)
        || path
            .to_string_lossy()
            .starts_with(pelt_preview::asset::BUILTIN)
    {
        return match start {
            Some(_) => Err(AnimationError::NotAnAsset.into()),
            None => Ok(None),
        };
    }
    let doc = pelt_io::load(path).map_err(AnimationError::Load)?;
    if doc.array("animations").is_empty() && start.is_none() {
        return Ok(None);
    }
    let rig = pelt_anim::rig::Rig::load(&doc).map_err(AnimationError::Load)?;
    let t = Timeline::new(rig.summary().animations, start, time, playing).map_err(|source| {
        AnimationError::UnknownClip {
            path: path.to_owned(),
            source,
        }
    })?;
    Ok(t.map(|t| (doc, t)))
}

/// The files an input depends on (the file, and a scene's assets).
fn dependencies(path: &Path, input: &Input) -> Vec<PathBuf> {
    let mut v = vec![path.to_owned()];
    if knobs::is_scene(path) {
        for o in &input.scene.objects {
            if !o
                .asset
                .to_string_lossy()
                .starts_with(pelt_preview::asset::BUILTIN)
            {
                v.push(o.asset.clone());
            }
        }
    }
    v.sort();
    v.dedup();
    v
}

/// The fur shells of the scene's fur objects (the largest), or None without fur.
fn max_shells(sv: &SceneView) -> Option<u32> {
    sv.plan
        .objects
        .iter()
        .filter_map(|o| o.fur)
        .map(|f| f.shells)
        .max()
}

impl Viewer {
    /// Loads `path` for a window of `surface`; an animated asset starts at `time` s of the
    /// clip `animation` (its first when None), playing when `playing`.
    pub fn open(
        preview: &mut Preview,
        path: &Path,
        settings: Settings,
        surface: Surface,
        target_ms: f64,
        (animation, time, playing): (Option<&str>, f32, bool),
    ) -> Result<Viewer, ViewError> {
        let anim = animation_of(path, animation, time, playing)?;
        let posed_at = anim.as_ref().map(|(_, t)| t.pose());
        // Framed on the first pose drawn, as `pelt render --animation` frames it; the camera
        // then stays while the clip plays.
        let input = load_posed(path, surface.size, posed_at.as_ref(), &settings.knobs)?;
        let (animated, timeline) = anim.unzip();
        let clock = (timeline.is_none() && input.scene.wind.is_some())
            .then_some(WindClock { time, playing });
        let orbit = Orbit::new(&input.scene.camera);
        let mut v = Viewer {
            path: path.to_owned(),
            watch: Watch::new(dependencies(path, &input)),
            full: prepare(
                preview,
                &input,
                settings.mode,
                &scene_of(&input, &settings.knobs, surface.size),
                window_output(surface),
            )?,
            input,
            settings,
            orbit,
            moved: false,
            budget: None,
            target_ms,
            pass_ms: Vec::new(),
            last_quality: None,
            timeline,
            clock,
            animated,
            posed_at,
            gpu_pose: None,
            reduced: None,
            refining: None,
            surface,
        };
        v.refresh(preview)?;
        Ok(v)
    }

    /// Draws the animated asset at the timeline's time, when it moved since the last pose
    /// (`pelt_preview::animate::follow` chooses GPU skinning or a CPU pose and upload).
    pub fn follow_timeline(&mut self, preview: &mut Preview) -> Result<(), ViewError> {
        let (Some(doc), Some(t)) = (&self.animated, &self.timeline) else {
            return Ok(());
        };
        let pose = t.pose();
        if self.posed_at.as_ref() == Some(&pose) {
            return Ok(());
        }
        // A new pose: the strands mode's mean starts again (its view is prepared anew).
        self.refining = None;
        let mut views = vec![&self.full];
        views.extend(self.reduced.as_ref().map(|r| &r.view));
        let asset = (&self.input.meshes[0], doc, self.path.as_path());
        let followed =
            animate::follow(preview, &views, asset, &pose).map_err(AnimationError::Follow)?;
        self.posed_at = Some(pose.clone());
        match followed {
            // Skinned on the GPU: views prepared later are posed too (`catch_up`).
            Followed::Skinned => self.gpu_pose = Some(pose),
            Followed::Upload(mesh) => {
                self.input.meshes[0] = *mesh;
                self.gpu_pose = None;
                self.full = prepare(
                    preview,
                    &self.input,
                    self.settings.mode,
                    &self.scene(),
                    window_output(self.surface),
                )?;
                self.reduced = None;
                preview.assets.sweep();
            }
        }
        // The wind blows at the timeline's time too.
        self.follow_time(preview)
    }

    /// Poses `sv` (prepared from the input, so at the pose it was loaded at) to the pose the
    /// GPU skinned the views to since, if it did.
    fn catch_up(&self, preview: &Preview, sv: &SceneView) -> Result<(), ViewError> {
        if let Some(p) = &self.gpu_pose {
            preview
                .pose(sv, &p.animation, p.time, &self.path)
                .map_err(AnimationError::Pose)?;
        }
        Ok(())
    }

    /// The scene as drawn at full quality: the input's, with the knobs and the camera, at the
    /// timeline's or the clock's time.
    pub fn scene(&self) -> Scene {
        let mut s = scene_of(&self.input, &self.settings.knobs, self.surface.size);
        if self.moved {
            s.camera = self.orbit.camera();
        }
        s.time = match (&self.timeline, &self.clock) {
            (Some(t), _) => t.time,
            (None, Some(c)) => c.time,
            (None, None) => 0.0,
        };
        s
    }

    /// The scene's time moved: a scene with wind is planned again at it (only uniforms
    /// change); the reduced view and the strands mode's mean start again.
    pub fn follow_time(&mut self, preview: &mut Preview) -> Result<(), ViewError> {
        if self.input.scene.wind.is_none() {
            return Ok(());
        }
        let scene = self.scene();
        preview.update(&mut self.full, &scene, self.settings.mode)?;
        self.reduced = None;
        self.refining = None;
        Ok(())
    }

    /// The scene at `q`.
    fn scene_at(&self, q: &Quality) -> Scene {
        let mut s = self.scene();
        s.lbuffer_scale = q.lbuffer_scale;
        if self.budget.is_some_and(|b| q.shells < b.costs.full.shells) {
            Knobs {
                shells: Some(ShellCount::Fixed(q.shells)),
                ..Knobs::default()
            }
            .apply(&mut s);
        }
        let scale = |v: u32| ((v as f32 * q.render_scale).round() as u32).max(1);
        s.output.width = scale(s.output.width);
        s.output.height = scale(s.output.height);
        s
    }

    /// Settings or size changed: the full-quality view follows (no asset is uploaded), and
    /// the budget is measured again when next needed.
    pub fn refresh(&mut self, preview: &mut Preview) -> Result<(), ViewError> {
        let scene = self.scene();
        preview.update(&mut self.full, &scene, self.settings.mode)?;
        self.budget = None;
        self.reduced = None;
        self.refining = None;
        Ok(())
    }

    /// The window was resized.
    pub fn resize(&mut self, preview: &mut Preview, size: (u32, u32)) -> Result<(), ViewError> {
        self.surface.size = (size.0.max(1), size.1.max(1));
        self.refresh(preview)
    }

    /// `F`: the scene's own camera back (for an asset, its default framing), keeping the
    /// direction the orbit looks from.
    pub fn frame(&mut self) {
        self.orbit.frame(&self.input.scene.camera);
        self.moved = true;
    }

    /// The camera moved by the user or a script.
    pub fn camera_moved(&mut self) {
        self.moved = true;
    }

    /// Opens `path` (a dropped file, or a reload of the same). On an error the last good
    /// scene stays and the error is returned.
    pub fn reload(&mut self, preview: &mut Preview, path: &Path) -> Result<(), ViewError> {
        let keep = self
            .timeline
            .as_ref()
            .filter(|_| path == self.path)
            .map(|t| (t.pose(), t.playing));
        let anim = match &keep {
            // A clip that no longer exists starts the file's first.
            Some((p, playing)) => animation_of(path, Some(&p.animation), p.time, *playing)
                .or_else(|_| animation_of(path, None, 0.0, *playing))?,
            None => animation_of(path, None, 0.0, true)?,
        };
        let posed_at = anim.as_ref().map(|(_, t)| t.pose());
        let input = load_posed(
            path,
            self.surface.size,
            posed_at.as_ref(),
            &self.settings.knobs,
        )?;
        let scene = scene_of(&input, &self.settings.knobs, self.surface.size);
        let full = prepare(
            preview,
            &input,
            self.settings.mode,
            &scene,
            window_output(self.surface),
        )?;
        let same = path == self.path;
        self.watch = Watch::new(dependencies(path, &input));
        self.path = path.to_owned();
        if !same {
            self.orbit = Orbit::new(&input.scene.camera);
            self.moved = false;
        }
        self.input = input;
        self.full = full;
        (self.animated, self.timeline) = anim.unzip();
        self.posed_at = posed_at;
        self.gpu_pose = None;
        self.refresh(preview)?;
        preview.assets.sweep();
        Ok(())
    }

    /// Whether the input (or an asset it names) changed on disk since the last call.
    pub fn input_changed(&mut self) -> bool {
        self.watch.changed()
    }

    /// Measures the full-quality frame's pass costs (and, with fur, the frame with one shell)
    /// for the budget and the overlay.
    pub fn measure(&mut self, preview: &mut Preview) -> Result<(), ViewError> {
        let scene = self.scene();
        let mode = self.settings.mode;
        let input = &self.input;
        let mut sv = prepare(preview, input, mode, &scene, ViewOutput::IMAGE)?;
        self.catch_up(preview, &sv)?;
        let t = preview.time(&sv, 1, 1)?;
        let split = |passes: &[(Pass, f64)]| {
            let lres = |p: Pass| {
                mode == pelt_preview::Mode::Inferred && builder(p).is_some_and(|d| d.at_lbuffer)
            };
            // The distance maps do not depend on the camera: a moving frame reuses them.
            let per_frame = |p: Pass| builder(p).is_none_or(|d| d.cached.is_none());
            passes
                .iter()
                .filter(|(p, _)| per_frame(*p))
                .fold(
                    (0.0, 0.0),
                    |(l, o), &(p, ms)| {
                        if lres(p) { (l + ms, o) } else { (l, o + ms) }
                    },
                )
        };
        let (lbuffer_ms, output_ms) = split(&t.passes);
        let shells = max_shells(&sv);
        let one_shell_ms = match shells {
            Some(n) if n > 1 => {
                let mut one = scene.clone();
                Knobs {
                    shells: Some(ShellCount::Fixed(1)),
                    ..Knobs::default()
                }
                .apply(&mut one);
                preview.update(&mut sv, &one, mode)?;
                split(&preview.time(&sv, 1, 1)?.passes).1
            }
            _ => output_ms,
        };
        let full = Quality {
            lbuffer_scale: scene.lbuffer_scale,
            shells: shells.unwrap_or(1),
            render_scale: 1.0,
        };
        self.pass_ms = t.passes;
        self.budget = Some(Budget::new(
            self.target_ms,
            Costs::fit(full, lbuffer_ms, output_ms, one_shell_ms),
        ));
        Ok(())
    }

    /// Draws one frame into `texture` (the window's), at full quality when `moving` is
    /// false. Returns the quality drawn.
    pub fn draw(
        &mut self,
        preview: &mut Preview,
        texture: &wgpu::TextureView,
        moving: bool,
    ) -> Result<Quality, ViewError> {
        if moving && self.budget.is_none() {
            self.measure(preview)?;
        }
        let q = match &self.budget {
            Some(b) => b.choose(moving),
            None => Quality {
                lbuffer_scale: self.scene().lbuffer_scale,
                shells: max_shells(&self.full).unwrap_or(1),
                render_scale: 1.0,
            },
        };
        let output = Output {
            view: texture,
            format: self.surface.format,
        };
        let full_quality = self.budget.is_none_or(|b| q == b.costs.full);
        let playing = self.timeline.as_ref().is_some_and(|t| t.playing);
        if self.settings.mode != pelt_preview::Mode::Strands || moving || playing {
            self.refining = None;
        }
        if full_quality && self.settings.mode == pelt_preview::Mode::Strands && !moving && !playing
        {
            self.refine(preview, output)?;
        } else if full_quality {
            let scene = self.scene();
            if self.moved {
                preview.look(&mut self.full, &scene.camera)?;
            }
            preview.draw_into(&self.full, texture)?;
        } else {
            let scene = self.scene_at(&q);
            self.draw_reduced(preview, &scene, output)?;
        }
        self.last_quality = Some(q);
        Ok(q)
    }

    /// Whether strands mode is still refining a still frame (the window should keep drawing).
    pub fn refining(&self) -> bool {
        self.settings.mode == pelt_preview::Mode::Strands
            && !self.timeline.as_ref().is_some_and(|t| t.playing)
            && self
                .refining
                .as_ref()
                .is_none_or(|r| r.mean.samples() < MAX_REFINE)
    }

    /// Samples per pixel of the strands mode's running mean (0 when not refining).
    pub fn refined_samples(&self) -> u32 {
        self.refining.as_ref().map_or(0, |r| r.mean.samples())
    }

    /// One more sample of the still strands frame, and the mean so far into `output`. A
    /// camera move keeps the view and restarts the mean; any other change of the scene or
    /// size prepares the view again.
    fn refine(&mut self, preview: &mut Preview, output: Output<'_>) -> Result<(), ViewError> {
        let scene = self.scene();
        let size = (scene.output.width, scene.output.height);
        let same_but_camera = |r: &Refining| {
            let mut s = r.scene.clone();
            s.camera = scene.camera;
            s == scene && r.mean.size() == size
        };
        match &mut self.refining {
            Some(r) if r.scene == scene && r.mean.size() == size => {}
            Some(r) if same_but_camera(r) => {
                preview.look(&mut r.view, &scene.camera)?;
                r.mean.restart();
                r.scene = scene;
                r.since = Instant::now();
            }
            _ => {
                let view = prepare(
                    preview,
                    &self.input,
                    pelt_preview::Mode::Strands,
                    &scene,
                    ViewOutput::IMAGE,
                )?;
                let mean = Progressive::new(&preview.renderer, size, self.surface.size);
                self.catch_up(preview, &view)?;
                self.refining = Some(Refining {
                    view,
                    mean,
                    scene,
                    since: Instant::now(),
                });
            }
        }
        if let Some(r) = &mut self.refining {
            if r.mean.samples() < MAX_REFINE {
                r.mean.step(preview, &mut r.view)?;
            }
            r.mean
                .show(&preview.renderer, output)
                .map_err(RenderError::from)?;
        }
        Ok(())
    }

    fn draw_reduced(
        &mut self,
        preview: &mut Preview,
        scene: &Scene,
        output: Output<'_>,
    ) -> Result<(), ViewError> {
        let size = (scene.output.width, scene.output.height);
        let fits = self
            .reduced
            .as_ref()
            .is_some_and(|r| r.view.targets.spec.output == size);
        if fits {
            if let Some(r) = &mut self.reduced {
                preview.update(&mut r.view, scene, self.settings.mode)?;
            }
        } else {
            let view = prepare(
                preview,
                &self.input,
                self.settings.mode,
                scene,
                ViewOutput::IMAGE,
            )?;
            let color = view.targets.color.as_ref().ok_or_else(|| {
                ViewError::Render(RenderError::from(pelt_preview::features::MissingInput {
                    pass: "upscale",
                    what: "the reduced frame".into(),
                }))
            })?;
            let upscale = Upscale::new(&preview.renderer, color, self.surface.size);
            self.catch_up(preview, &view)?;
            self.reduced = Some(Reduced { view, upscale });
        }
        if let Some(r) = &self.reduced {
            preview.draw(&r.view)?;
            pelt_preview::frame::upscale(&preview.renderer, &r.upscale, output)
                .map_err(RenderError::from)?;
        }
        Ok(())
    }

    /// The last frame took `ms` (drawn, presented, waited for): a reduced one teaches the
    /// budget what its model leaves out.
    pub fn observe(&mut self, ms: f64) {
        if let (Some(b), Some(q)) = (&mut self.budget, self.last_quality)
            && q != b.costs.full
        {
            b.observe(&q, ms);
        }
    }

    /// The full-quality frame of the current camera and settings as an image (a screenshot:
    /// rendered again into a texture of its own, from the same cached assets).
    pub fn screenshot(&self, preview: &mut Preview) -> Result<Image, ViewError> {
        // Strands mode shows its running mean: the screenshot is that mean.
        if let Some(r) = &self.refining
            && r.mean.samples() > 0
            && r.scene == self.scene()
        {
            return Ok(r.mean.image());
        }
        let sv = prepare(
            preview,
            &self.input,
            self.settings.mode,
            &self.scene(),
            ViewOutput::IMAGE,
        )?;
        self.catch_up(preview, &sv)?;
        Ok(preview.render(&sv)?)
    }

    /// The status as lines (the overlay): input and settings; frame time and, while
    /// moving, the quality the budget chose; the measured pass times.
    pub fn status_lines(&self, frame_ms: f64) -> Vec<String> {
        let s = self.scene();
        let shells = max_shells(&self.full);
        let mut first = format!(
            "{} | {}",
            self.path.file_name().map_or_else(
                || self.path.display().to_string(),
                |n| n.to_string_lossy().into_owned()
            ),
            self.settings.mode
        );
        if self.settings.mode == pelt_preview::Mode::Inferred {
            first += &format!(
                ", L-buffer {:.3}, DSF {}",
                s.lbuffer_scale,
                if s.dsf { "on" } else { "off" }
            );
        }
        if self.settings.mode == pelt_preview::Mode::Strands {
            first += &match self.refining.as_ref() {
                Some(r) => refine_status(r.mean.samples(), r.since.elapsed().as_secs_f64()),
                None => ", explicit strands (one sample a frame while moving)".to_owned(),
            };
        } else if let Some(n) = shells {
            let fins = s
                .objects
                .iter()
                .any(|o| matches!(o.material, Material::Fur(f) if f.fins_with(s.fur_coverage)));
            first += &format!(
                ", {n} shells{}, {:?}",
                if fins { " + fins" } else { "" },
                s.fur_blend
            );
        }
        let mut second = format!("frame {frame_ms:.0} ms");
        if let (Some(q), Some(b)) = (self.last_quality, &self.budget)
            && q != b.costs.full
        {
            second += &format!(
                " (moving: L {:.2}, {} shells, {:.0} % res; budget {:.0} ms)",
                q.lbuffer_scale,
                q.shells,
                q.render_scale * 100.0,
                b.target_ms
            );
        }
        let mut lines = vec![first, second];
        if let Some(t) = &self.timeline {
            lines.push(t.status());
        }
        if let Some(c) = &self.clock {
            lines.push(c.status());
        }
        if !self.pass_ms.is_empty() {
            let p: Vec<String> = self
                .pass_ms
                .iter()
                .map(|(p, ms)| format!("{} {ms:.0}", p.name()))
                .collect();
            lines.push(format!("passes (ms, full quality): {}", p.join(", ")));
        }
        lines
    }

    /// The status in one line (title bar, scripted mode's log).
    pub fn status(&self, frame_ms: f64) -> String {
        format!("pelt view: {}", self.status_lines(frame_ms).join(" | "))
    }
}

/// Loads an input for a window of `size` (an asset's default scene takes the window's
/// size), posed at `pose` when there is one, with the load-time knobs of `k` (the texture
/// limit; the others apply to the scene after loading). Load warnings go to standard error.
fn load_posed(
    path: &Path,
    size: (u32, u32),
    pose: Option<&pelt_preview::asset::PoseAt>,
    k: &Knobs,
) -> Result<Input, ViewError> {
    let load = Knobs {
        max_texture: k.max_texture,
        ..Knobs::default()
    };
    let input = knobs::load_at(path, &load, size, pose).map_err(ViewError::Input)?;
    for w in input.meshes.iter().flat_map(|m| &m.warnings) {
        eprintln!("pelt view: warning: {w}");
    }
    Ok(input)
}

/// The input's scene with the knobs applied, at the window's size.
fn scene_of(input: &Input, knobs: &Knobs, size: (u32, u32)) -> Scene {
    let mut s = input.scene.clone();
    knobs.apply(&mut s);
    s.output.width = size.0;
    s.output.height = size.1;
    s
}

/// What the window draws into: its surface's texture, given each frame.
fn window_output(surface: Surface) -> ViewOutput {
    ViewOutput {
        format: surface.format,
        own_color: false,
    }
}

/// Prepares `scene` with `input`'s meshes for `output` (the window, or a texture of its own).
fn prepare(
    preview: &mut Preview,
    input: &Input,
    mode: pelt_preview::Mode,
    scene: &Scene,
    output: ViewOutput,
) -> Result<SceneView, ViewError> {
    Ok(preview.prepare_view(scene, &input.meshes, &input.mesh_of, mode, output)?)
}

/// Why the viewer stopped or an action failed.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// The input could not be loaded.
    #[error(transparent)]
    Input(knobs::InputError),
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The window system failed.
    #[error("window: {0}")]
    Window(#[from] WindowError),
    /// Writing a file failed.
    #[error(transparent)]
    Frame(#[from] pelt_preview::FrameError),
    /// The asset's animation cannot be played (a clip that does not exist, a bad rig).
    #[error(transparent)]
    Animation(#[from] AnimationError),
}

/// What the window system refused.
#[derive(Debug, thiserror::Error)]
pub enum WindowError {
    /// The event loop could not be made or run.
    #[error(transparent)]
    EventLoop(#[from] winit::error::EventLoopError),
    /// The window could not be made.
    #[error(transparent)]
    Os(#[from] winit::error::OsError),
    /// The window's surface offers no texture format.
    #[error("the surface offers no format")]
    NoFormat,
    /// The surface reported a validation error for a frame.
    #[error("the surface reported a validation error")]
    SurfaceValidation,
}

/// Why the asset's animation cannot be played. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum AnimationError {
    /// `--animation` was given for a scene file (or a built-in asset).
    #[error("--animation needs an asset (.glb, .gltf), not a scene file")]
    NotAnAsset,
    /// The asset, or its rig, could not be read.
    #[error(transparent)]
    Load(pelt_io::IoError),
    /// The asset has no clip by the name asked for.
    #[error("{}: {source}", path.display())]
    UnknownClip {
        /// The asset.
        path: PathBuf,
        /// The name asked for and the names it has.
        #[source]
        source: UnknownClip,
    },
    /// The asset could not be drawn at the timeline's pose.
    #[error(transparent)]
    Follow(animate::AnimateError),
    /// The GPU could not skin a view to the timeline's pose.
    #[error(transparent)]
    Pose(pelt_preview::PoseError),
}

/// Time since `t`, in milliseconds.
pub fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The strands status counts the samples against the most, fills its bar and estimates
    /// the time left at the rate so far; a finished mean says so, with no estimate.
    #[test]
    fn the_strands_status_shows_a_bar_and_the_time_left() {
        let s = refine_status(1024, 10.0);
        assert!(s.contains("1024 of 4096 samples"), "{s}");
        assert!(s.contains("[####------------]"), "{s}");
        assert!(s.contains("about 30 s left"), "{s}");
        let slow = refine_status(64, 2.0);
        assert!(slow.contains("about 2 min left"), "{slow}");
        let done = refine_status(MAX_REFINE, 100.0);
        assert!(done.contains("(done)") && !done.contains("left"), "{done}");
        assert!(refine_status(0, 0.0).contains("starting"));
    }
}
