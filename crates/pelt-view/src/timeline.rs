//! `pelt view`'s animation timeline: which clip of an animated asset plays, where in it, and
//! whether it plays. Space plays and pauses, `,` and `.` step a frame back and forward (and
//! pause), `C` picks the next clip; while playing, time advances with the wall clock (in the
//! scripted mode, by one 1/30 s frame per frame drawn, so scripted runs are deterministic)
//! and wraps at the end of the clip. The viewer poses the asset at [`Timeline::pose`].

use pelt_anim::rig::ClipSummary;
use pelt_preview::asset::PoseAt;

/// One step of `,` and `.` (and of the scripted mode's playback).
pub const FRAME_S: f32 = 1.0 / 30.0;

/// The clips of an asset and the playhead.
#[derive(Debug, Clone)]
pub struct Timeline {
    /// Every clip (name, first and last key time).
    pub clips: Vec<ClipSummary>,
    /// The clip playing.
    pub clip: usize,
    /// Seconds (within the clip's key range).
    pub time: f32,
    /// Whether time advances.
    pub playing: bool,
}

/// A clip name the asset does not have.
#[derive(Debug, Clone, thiserror::Error)]
#[error("no animation {name:?} (the asset has: {})", known.join(", "))]
pub struct UnknownClip {
    /// The name asked for.
    pub name: String,
    /// The names it has.
    pub known: Vec<String>,
}

impl Timeline {
    /// A timeline over `clips` at `time` s of the clip named `start` (the first clip when
    /// None); None when there are no clips.
    pub fn new(
        clips: Vec<ClipSummary>,
        start: Option<&str>,
        time: f32,
        playing: bool,
    ) -> Result<Option<Timeline>, UnknownClip> {
        if clips.is_empty() {
            return match start {
                Some(name) => Err(UnknownClip {
                    name: name.to_owned(),
                    known: Vec::new(),
                }),
                None => Ok(None),
            };
        }
        let clip = match start {
            Some(name) => clips
                .iter()
                .position(|c| c.name == name)
                .ok_or_else(|| UnknownClip {
                    name: name.to_owned(),
                    known: clips.iter().map(|c| c.name.clone()).collect(),
                })?,
            None => 0,
        };
        let c = &clips[clip];
        let time = time.clamp(c.start, c.end.max(c.start));
        Ok(Some(Timeline {
            clips,
            clip,
            time,
            playing,
        }))
    }

    fn current(&self) -> &ClipSummary {
        &self.clips[self.clip]
    }

    /// `t` wrapped into the clip's key range.
    fn wrapped(&self, t: f32) -> f32 {
        let c = self.current();
        let len = c.end - c.start;
        if len <= 0.0 || !t.is_finite() {
            return c.start;
        }
        c.start + (t - c.start).rem_euclid(len)
    }

    /// Advances `dt` seconds while playing; returns whether the time changed.
    pub fn advance(&mut self, dt: f32) -> bool {
        if !self.playing || dt <= 0.0 {
            return false;
        }
        let before = self.time;
        self.time = self.wrapped(self.time + dt);
        self.time != before
    }

    /// Space: play or pause.
    pub fn toggle(&mut self) {
        self.playing = !self.playing;
    }

    /// `,` / `.`: `frames` frames back or forward (wrapping), paused.
    pub fn step(&mut self, frames: i32) {
        self.playing = false;
        self.time = self.wrapped(self.time + frames as f32 * FRAME_S);
    }

    /// `C`: the next clip, from its start.
    pub fn next_clip(&mut self) {
        self.clip = (self.clip + 1) % self.clips.len();
        self.time = self.current().start;
    }

    /// The pose to draw.
    pub fn pose(&self) -> PoseAt {
        PoseAt {
            animation: self.current().name.clone(),
            time: self.time,
        }
    }

    /// One line for the overlay and the title: clip, time, state.
    pub fn status(&self) -> String {
        let c = self.current();
        format!(
            "{} {:.2}/{:.2} s {} (clip {}/{}; Space play/pause, , . step, C clip)",
            c.name,
            self.time,
            c.end,
            if self.playing { "playing" } else { "paused" },
            self.clip + 1,
            self.clips.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clips() -> Vec<ClipSummary> {
        let clip = |name: &str, end: f32| ClipSummary {
            name: name.into(),
            start: 0.0,
            end,
            duration: end,
            channels: 1,
        };
        vec![clip("Survey", 3.0), clip("Walk", 0.7), clip("Run", 0.5)]
    }

    #[test]
    fn playing_wraps_at_the_end_and_pausing_holds() {
        let mut t = Timeline::new(clips(), Some("Walk"), 0.6, true)
            .expect("known")
            .expect("clips");
        assert!(t.advance(0.2));
        assert!((t.time - 0.1).abs() < 1e-5, "{}", t.time);
        t.toggle();
        assert!(!t.advance(0.2));
        assert!((t.time - 0.1).abs() < 1e-5);
        // Four frames back from 0.1 s passes the start: wrapped to the end of the clip.
        t.step(-4);
        assert!(
            (t.time - (0.1 - 4.0 * FRAME_S + 0.7)).abs() < 1e-5,
            "{}",
            t.time
        );
        t.toggle();
        t.step(1);
        assert!(!t.playing, "stepping pauses");
    }

    #[test]
    fn clips_cycle_from_their_start_and_a_wrong_name_lists_the_right_ones() {
        let mut t = Timeline::new(clips(), None, 9.0, false)
            .expect("known")
            .expect("clips");
        assert_eq!((t.clip, t.time), (0, 3.0), "time clamped to the clip");
        t.next_clip();
        t.next_clip();
        assert_eq!(t.pose().animation, "Run");
        t.next_clip();
        assert_eq!((t.clip, t.time), (0, 0.0));
        let e = Timeline::new(clips(), Some("Trot"), 0.0, false).expect_err("unknown");
        assert!(e.to_string().contains("Survey, Walk, Run"), "{e}");
        assert!(
            Timeline::new(Vec::new(), None, 0.0, true)
                .expect("none")
                .is_none()
        );
        assert!(Timeline::new(Vec::new(), Some("Walk"), 0.0, true).is_err());
    }
}
