//! Shells by screen size: how many shells a fur object needs for the length its fur projects
//! to on screen. Each shell stands for a layer of the fur (Lengyel et al. 2001; Revie §2.3.1);
//! once a layer is under a pixel deep on screen, more layers change nothing a viewer sees, so
//! the count falls with the fur's projected length, down to a floor, and never exceeds the
//! material's `shells` (the artist's count, now the most drawn). The numbers are measured by
//! `pelt sweep`'s curves of error against shell count at several distances
//! (docs/sweep.md, "Shells by screen size"): the count at each curve's knee (the smallest
//! count a doubling improves by under FLIP 0.003) is the fur's projected length in pixels,
//! rounded up, from 3 shells at 2.4 px to 16 at 22 px and beyond. The bake writes the rule
//! into the fur manifest (`shellRule`), so pelt and every runtime use the same numbers.

use serde::{Deserialize, Serialize};

/// The rule: `clamp(⌈pixels / pixelsPerShell⌉, min, shells)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct ShellRule {
    /// The fur's projected length (pixels) one shell covers.
    pub pixels_per_shell: f64,
    /// The fewest shells drawn, however small the fur.
    pub min: u32,
}

impl ShellRule {
    /// The measured rule (module docs): one shell per pixel of fur, at least 3.
    pub const MEASURED: ShellRule = ShellRule {
        pixels_per_shell: 1.0,
        min: 3,
    };

    /// The shell count for fur whose longest strand projects to `pixels` on screen, at most
    /// `max` (the material's `shells`). Non-finite lengths (the eye inside the fur) get `max`.
    pub fn shells(&self, pixels: f64, max: u32) -> u32 {
        let max = max.max(1);
        let min = self.min.clamp(1, max);
        if !pixels.is_finite() {
            return max;
        }
        let n = (pixels.max(0.0) / self.pixels_per_shell).ceil();
        if n >= f64::from(max) {
            max
        } else {
            (n as u32).clamp(min, max)
        }
    }

    /// Why the rule is unusable, if it is (`pixelsPerShell` must be finite and positive,
    /// `min` 1 to 1024).
    pub fn invalid(&self) -> Option<String> {
        if !(self.pixels_per_shell.is_finite() && self.pixels_per_shell > 0.0) {
            return Some(format!(
                "pixelsPerShell must be a positive number, got {}",
                self.pixels_per_shell
            ));
        }
        if !(1..=1024).contains(&self.min) {
            return Some(format!("min must be 1 to 1024, got {}", self.min));
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_count_falls_with_the_projected_length_between_the_floor_and_the_material() {
        let r = ShellRule::MEASURED;
        assert_eq!(r.shells(0.0, 16), 3);
        assert_eq!(r.shells(2.4, 16), 3);
        assert_eq!(r.shells(3.8, 16), 4);
        assert_eq!(r.shells(6.0, 16), 6);
        assert_eq!(r.shells(10.6, 16), 11);
        assert_eq!(r.shells(22.0, 16), 16);
        assert_eq!(r.shells(1e30, 16), 16);
        assert_eq!(r.shells(f64::INFINITY, 16), 16);
        assert_eq!(r.shells(f64::NAN, 16), 16);
        // A material with fewer shells than the floor draws its own count.
        assert_eq!(r.shells(0.5, 2), 2);
        assert_eq!(r.shells(5.0, 0), 1);
        let coarse = ShellRule {
            pixels_per_shell: 2.0,
            min: 1,
        };
        assert_eq!(coarse.shells(7.0, 64), 4);
        assert!(coarse.invalid().is_none());
        assert!(
            ShellRule {
                pixels_per_shell: 0.0,
                min: 1
            }
            .invalid()
            .is_some()
        );
        assert!(
            ShellRule {
                pixels_per_shell: 1.0,
                min: 0
            }
            .invalid()
            .is_some()
        );
    }
}
