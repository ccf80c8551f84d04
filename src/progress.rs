//! Progress of long work on standard error: a bar with an estimate on a terminal
//! (`indicatif`), a plain line per step otherwise (logs, CI), nothing with `-q`.

use std::io::IsTerminal as _;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// How often, at most, a step is printed as a line when standard error is not a terminal.
const LINE_EVERY: Duration = Duration::from_secs(5);

/// One piece of long work's progress.
pub struct Progress {
    bar: Option<ProgressBar>,
    lines: bool,
    last_line: Option<Instant>,
    started: Instant,
    what: String,
}

impl Progress {
    /// Progress of `what` over `total` steps (`quiet`: silent); `short` names it on the bar.
    pub fn new((what, short): (&str, &str), total: u64, quiet: bool) -> Progress {
        let terminal = std::io::stderr().is_terminal();
        let bar = (!quiet && terminal).then(|| {
            let b = ProgressBar::new(total);
            // The message first and the bar in what is left: indicatif drops a wide message
            // that does not fit the terminal's width, never the bar.
            if let Ok(style) = ProgressStyle::with_template(
                "{spinner} {prefix}: {msg} [{wide_bar}] {pos}/{len}, at most {eta} left",
            ) {
                b.set_style(style);
            }
            b.set_prefix(short.to_owned());
            b.enable_steady_tick(Duration::from_millis(200));
            b
        });
        Progress {
            bar,
            lines: !quiet && !terminal,
            last_line: None,
            started: Instant::now(),
            what: what.to_owned(),
        }
    }

    /// Says something once, above the bar (or as a line).
    pub fn say(&self, text: &str) {
        match &self.bar {
            Some(b) => b.println(text),
            None if self.lines => eprintln!("{text}"),
            None => {}
        }
    }

    /// Step `pos` of the total reached; `msg` says where the work stands. Lines (without a
    /// terminal) come every few seconds (work shorter than that prints none), and always when
    /// `force` is set.
    pub fn set(&mut self, pos: u64, msg: &str, force: bool) {
        if let Some(b) = &self.bar {
            b.set_position(pos);
            b.set_message(msg.to_owned());
            return;
        }
        if !self.lines {
            return;
        }
        let due = self.last_line.unwrap_or(self.started).elapsed() >= LINE_EVERY;
        if force || due {
            eprintln!("{}: {msg}", self.what);
            self.last_line = Some(Instant::now());
        }
    }

    /// Sets the total number of steps.
    pub fn set_length(&self, total: u64) {
        if let Some(b) = &self.bar {
            b.set_length(total);
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// The strand reference's steps shown on a [`Progress`]: samples per pixel (spp), the two
/// halves' FLIP against the target, time (short enough for an 80-column terminal's bar); a
/// line at its first frame and at every check.
#[derive(Default)]
pub struct StrandSteps {
    last_check: Option<f32>,
}

impl StrandSteps {
    /// Shows step `s`.
    pub fn show(&mut self, bar: &mut Progress, s: &pelt_measure::strands::Step) {
        bar.set_length(u64::from(s.max_frames));
        let flip = s
            .half_vs_half
            .map_or(String::new(), |f| format!(", FLIP {f:.4} of {}", s.target));
        let msg = if s.frames == 0 {
            format!("{} strands ready, {:.0} s", s.strands, s.elapsed)
        } else {
            format!("{} spp{flip}, {:.0} s", s.samples, s.elapsed)
        };
        let checked = s.half_vs_half != self.last_check;
        self.last_check = s.half_vs_half;
        bar.set(u64::from(s.frames), &msg, s.frames <= 1 || checked);
    }
}
