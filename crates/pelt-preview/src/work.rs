//! What a frame's render passes ask of the rasterizer, counted by the GPU itself: per pass,
//! the fragment-shader invocations (a pipeline-statistics query, where the adapter has them)
//! and the samples that passed the depth test and were written (an occlusion query, where it
//! counts them: Vulkan). The profile's last two columns (`pelt render --bench`), and what the
//! light pass's guard test compares with the work its scissor rectangles and depth rejection
//! should leave (Kircher & Lawrance §2.2): counts, not times, so a regression fails a test on
//! any machine.
//!
//! What a driver counts as an invocation is its own: lavapipe (llvmpipe) runs the fragment
//! shader on 4×4 blocks and counts 16 per block it enters, before the depth test, so there the
//! invocations follow the scissor and the samples follow the depth test.

use crate::readback::{FrameError, encoder, map_read, query_buffers};
use crate::recipe::{Queries, Recipe};
use crate::renderer::Renderer;

/// One render pass's counted work.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Work {
    /// Fragment-shader invocations (`None`: the adapter has no pipeline-statistics queries).
    pub fragments: Option<u64>,
    /// Samples that passed the depth test and were written (`None`: the back end's occlusion
    /// queries do not count).
    pub samples: Option<u64>,
}

impl std::ops::AddAssign for Work {
    fn add_assign(&mut self, o: Work) {
        let add = |a: Option<u64>, b: Option<u64>| match (a, b) {
            (Some(a), Some(b)) => Some(a + b),
            (a, b) => a.or(b),
        };
        self.fragments = add(self.fragments, o.fragments);
        self.samples = add(self.samples, o.samples);
    }
}

/// Encodes `recipes` once, in order, with their pipelines prepared, counting each render
/// pass's work; `None` for compute passes and copies. Every count is `None` where the device
/// counts neither.
pub fn count(r: &Renderer, recipes: &[Recipe<'_>]) -> Result<Vec<Option<Work>>, FrameError> {
    let gpu = &r.gpu;
    let rendered = recipes.iter().filter(|p| p.renders()).count() as u32;
    let set = |ty, label| {
        gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some(label),
            ty,
            count: rendered.max(1),
        })
    };
    let samples = gpu
        .samples
        .then(|| set(wgpu::QueryType::Occlusion, "samples"));
    let fragments = gpu.statistics.then(|| {
        let ty = wgpu::PipelineStatisticsTypes::FRAGMENT_SHADER_INVOCATIONS;
        set(wgpu::QueryType::PipelineStatistics(ty), "fragments")
    });
    let mut enc = encoder(r);
    let mut k = 0;
    for p in recipes {
        let mut q = Queries::default();
        if p.renders() {
            q.occlusion = samples.as_ref().map(|s| (s, k));
            q.statistics = fragments.as_ref().map(|s| (s, k));
            k += 1;
        }
        p.encode(r, &mut enc, q)?;
    }
    let samples = samples.as_ref().map(|s| resolve(r, &mut enc, s, k));
    let fragments = fragments.as_ref().map(|s| resolve(r, &mut enc, s, k));
    gpu.queue.submit([enc.finish()]);
    let read = |b: Option<wgpu::Buffer>| -> Result<Option<Vec<u64>>, FrameError> {
        let Some(b) = b else { return Ok(None) };
        let v = bytemuck::cast_slice::<u8, u64>(&map_read(r, &b)?).to_vec();
        Ok(Some(v))
    };
    let (samples, fragments) = (read(samples)?, read(fragments)?);
    let mut k = 0;
    Ok(recipes
        .iter()
        .map(|p| {
            p.renders().then(|| {
                let at = |v: &Option<Vec<u64>>| v.as_ref().map(|v| v[k]);
                let w = Work {
                    fragments: at(&fragments),
                    samples: at(&samples),
                };
                k += 1;
                w
            })
        })
        .collect())
}

/// Resolves the first `n` queries of `set` into a mappable buffer of `n` u64s.
fn resolve(
    r: &Renderer,
    enc: &mut wgpu::CommandEncoder,
    set: &wgpu::QuerySet,
    n: u32,
) -> wgpu::Buffer {
    let bytes = u64::from(n.max(1)) * 8;
    let (resolved, read) = query_buffers(r, "counted work", bytes);
    if n > 0 {
        enc.resolve_query_set(set, 0..n, &resolved, 0);
        enc.copy_buffer_to_buffer(&resolved, 0, &read, 0, bytes);
    }
    read
}
