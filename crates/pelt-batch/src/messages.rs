//! What a batch run says as text, for any front end: each input's outcome (baked, with its
//! counts and warnings; up to date; failed), the batch's one-line summary
//! ([`crate::report::Summary`]'s `Display`) and its failures. `pelt bake` prints these.

use crate::{Job, JobError, Outcome, Status};

/// The lines that report `o`, the outcome of `job`: the first says what happened, the rest are
/// the bake's warnings. `batch` is whether the job is one of several (a lone failure reads as
/// pelt's error, one of many as a `FAILED` line).
pub fn outcome_lines(job: &Job, o: &Outcome, batch: bool) -> Vec<String> {
    match &o.status {
        Status::Baked(b) => {
            let r = &b.bake;
            let mut v = vec![format!(
                "baked {} -> {}: {} primitives, {} vertices, {} triangles, {} warnings",
                job.input.display(),
                job.output.display(),
                r.primitives_baked,
                r.vertices,
                r.triangles,
                r.warnings.len()
            )];
            v.extend(
                r.warnings
                    .iter()
                    .map(|w| format!("warning: {}: {w}", job.input.display())),
            );
            v
        }
        Status::UpToDate => vec![format!("up to date: {}", job.output.display())],
        Status::Failed(e) if !batch => vec![format!("pelt: {e}")],
        Status::Failed(e) => vec![format!("FAILED {e}")],
    }
}

/// The failures' messages, in the order planned (each names the file and the place).
pub fn failures(outcomes: &[Outcome]) -> Vec<&JobError> {
    outcomes
        .iter()
        .filter_map(|o| match &o.status {
            Status::Failed(e) => Some(e),
            _ => None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;
    use crate::report::Summary;

    fn job() -> Job {
        Job {
            input: PathBuf::from("in/a.glb"),
            output: PathBuf::from("out/a.glb"),
        }
    }

    fn outcome(status: Status) -> Outcome {
        Outcome {
            status,
            reads: vec![],
        }
    }

    #[test]
    fn lines_say_what_happened_to_each_input() {
        let up = outcome(Status::UpToDate);
        assert_eq!(outcome_lines(&job(), &up, true), ["up to date: out/a.glb"]);
        let invalid = |file: &str, place: &str, message: &str| {
            Status::Failed(JobError::Asset(pelt_io::IoError::invalid(
                std::path::Path::new(file),
                place,
                message,
            )))
        };
        let failed = outcome(invalid("in/a.glb", "accessor 3", "out of range"));
        assert_eq!(
            outcome_lines(&job(), &failed, true),
            ["FAILED in/a.glb: accessor 3: out of range"]
        );
        assert_eq!(
            outcome_lines(&job(), &failed, false),
            ["pelt: in/a.glb: accessor 3: out of range"]
        );
        let all = [
            up,
            failed,
            outcome(invalid("b.glb", "buffers[0]", "missing")),
        ];
        let messages: Vec<String> = failures(&all).iter().map(ToString::to_string).collect();
        assert_eq!(
            messages,
            [
                "in/a.glb: accessor 3: out of range",
                "b.glb: buffers[0]: missing"
            ]
        );
        let s = Summary::of(&all, 2, 1234.0);
        assert_eq!(
            s.to_string(),
            "3 inputs: 0 baked, 1 up to date, 2 failed in 1.23 s (2 jobs)"
        );
    }
}
