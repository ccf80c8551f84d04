// fur_prepass.wgsl: the fur in Bevy's prepass and shadow passes: the same vertex stage as
// the main pass (the shells pushed out), and a fragment stage that keeps a shell's fragment
// with the probability of its layer's opacity (a hashed alpha test), so that a shadow map's
// texel is lit through the fur with the probability ∏(1 − αᵢ), the layers' transmittance,
// which the map's filtering averages: the fur casts by its coverage, as in pelt.

#import bevy_pelt::fur_shell::{FurVertex, FurVarying, fur, shell_vertex, coverage, hash3}
#ifdef PREPASS_FRAGMENT
#import bevy_pbr::prepass_io::FragmentOutput
#endif

@vertex
fn vertex(v: FurVertex) -> FurVarying {
    return shell_vertex(v);
}

// Discards the fragment unless its layer's hashed coverage keeps it.
fn hashed(in: FurVarying) {
    let a = coverage(in);
    if a <= hash3(vec3<f32>(in.position.xy, fur.shell.x)) {
        discard;
    }
}

#ifdef PREPASS_FRAGMENT
@fragment
fn fragment(in: FurVarying) -> FragmentOutput {
    hashed(in);
    var out: FragmentOutput;
#ifdef NORMAL_PREPASS
    out.normal = vec4<f32>(normalize(in.world_normal) * 0.5 + vec3<f32>(0.5), 1.0);
#endif
#ifdef MOTION_VECTOR_PREPASS
    out.motion_vector = vec2<f32>(0.0);
#endif
#ifdef UNCLIPPED_DEPTH_ORTHO_EMULATION
    out.frag_depth = in.unclipped_depth;
#endif
    return out;
}
#else
@fragment
fn fragment(in: FurVarying) {
    hashed(in);
}
#endif
