// The runtime's shaders (GLSL ES 3.00 for three's ShaderMaterial): the shells and fins of
// pelt's forward mode (shaders/shells.wgsl, fins.wgsl, fur_light_forward.wgsl) and its
// forward opaque surface and procedural sky (forward.wgsl, sky.wgsl). Every formula they share
// with pelt comes from the generated library (generated/pelt-glsl.js, naga's translation of
// shaders/*.wgsl); what is written here is only the plumbing: three's attributes, skinning
// chunks and light uniforms in, pelt's `Frame`, `Object` and `Light` structs filled from them.

import { peltGlsl } from './generated/pelt-glsl.js';

/** pelt_scene::shading: the specular power and strength every pelt surface uses. */
export const SPECULAR_POWER = 32.0;
export const SPECULAR_STRENGTH = 0.25;

// pelt's lights from three's uniforms: a point light's view-space position and `distance`
// (pelt's radius, where its windowed falloff reaches zero), a directional light's view-space
// direction toward it; colour × intensity, and w its luminance; no cone (common.wgsl's Light).
const lightsGlsl = /* glsl */ `
Light pelt_point(int i) {
  Light l;
  l.cone = vec4(0.0, 0.0, 0.0, 1.0);
#if NUM_POINT_LIGHTS > 0
  l.position_radius = vec4(pointLights[i].position, pointLights[i].distance);
  l.color = vec4(pointLights[i].color, dot(pointLights[i].color, vec3(0.2126, 0.7152, 0.0722)));
#endif
  return l;
}
Light pelt_sun(int i) {
  Light l;
  l.cone = vec4(0.0, 0.0, 0.0, 1.0);
#if NUM_DIR_LIGHTS > 0
  l.position_radius = vec4(directionalLights[i].direction, 0.0);
  l.color = vec4(directionalLights[i].color, dot(directionalLights[i].color, vec3(0.2126, 0.7152, 0.0722)));
#endif
  return l;
}
`;

// Shadow lookups of three's maps, by light (1 where the light casts none): three sorts the
// shadow-casting lights of a kind first, so light `which` has shadow `which`.
const shadowGlsl = /* glsl */ `
float pelt_point_shadow(int which) {
  float s = 1.0;
#if defined( USE_SHADOWMAP ) && NUM_POINT_LIGHT_SHADOWS > 0
  #pragma unroll_loop_start
  for ( int i = 0; i < NUM_POINT_LIGHT_SHADOWS; i ++ ) {
    if (UNROLLED_LOOP_INDEX == which) {
      PointLightShadow ps = pointLightShadows[ UNROLLED_LOOP_INDEX ];
      s = getPointShadow( pointShadowMap[ UNROLLED_LOOP_INDEX ], ps.shadowMapSize, ps.shadowIntensity, ps.shadowBias, ps.shadowRadius, vPointShadowCoord[ UNROLLED_LOOP_INDEX ], ps.shadowCameraNear, ps.shadowCameraFar );
    }
  }
  #pragma unroll_loop_end
#endif
  return s;
}
float pelt_sun_shadow(int which) {
  float s = 1.0;
#if defined( USE_SHADOWMAP ) && NUM_DIR_LIGHT_SHADOWS > 0
  #pragma unroll_loop_start
  for ( int i = 0; i < NUM_DIR_LIGHT_SHADOWS; i ++ ) {
    if (UNROLLED_LOOP_INDEX == which) {
      DirectionalLightShadow ds = directionalLightShadows[ UNROLLED_LOOP_INDEX ];
      s = getShadow( directionalShadowMap[ UNROLLED_LOOP_INDEX ], ds.shadowMapSize, ds.shadowIntensity, ds.shadowBias, ds.shadowRadius, vDirectionalShadowCoord[ UNROLLED_LOOP_INDEX ] );
    }
  }
  #pragma unroll_loop_end
#endif
  return s;
}
`;

// Every light of the view added into `diffuse` and `specular` (the loop of forward.wgsl and
// fur_light_forward.wgsl): `term` is the GLSL of one light's vec4 (rgb diffuse, a specular
// intensity) of `l` (a Light) and `r` (its reach at `p`), weighted by what its shadow map lets
// through; the specular intensity takes the light's colour back (Light.color.w, luminance).
function lightLoop(term) {
  return [['pelt_point', 'pelt_point_shadow', 'NUM_POINT_LIGHTS', 'false'], ['pelt_sun', 'pelt_sun_shadow', 'NUM_DIR_LIGHTS', 'true']]
    .map(([light, shadow, count, sun]) => `#if ${count} > 0
  for (int i = 0; i < ${count}; i++) {
    Light l = ${light}(i);
    vec4 r = light_reach(p, l, ${sun});
    vec4 s = ${term} * ${shadow}(i);
    diffuse += s.rgb;
    if (l.color.w > 0.0) specular += s.a * l.color.rgb / l.color.w;
  }
#endif`)
    .join('\n');
}

// Kajiya-Kay over every light (fur_light_forward.wgsl's fur_lighting): diffuse (ambient
// included) and specular colour for a strand along `t` at view-space `p`.
const furLightingGlsl = /* glsl */ `
void pelt_fur_lighting(vec3 p, vec3 t, out vec3 diffuse, out vec3 specular) {
  diffuse = ambientLightColor;
  specular = vec3(0.0);
${lightLoop('strand_light(p, t, r, l, ' + SPECULAR_POWER.toFixed(1) + ')')}
}
`;

const fragmentHead = /* glsl */ `
#include <common>
#include <packing>
#include <lights_pars_begin>
#include <shadowmap_pars_fragment>
${peltGlsl}
${lightsGlsl}
${shadowGlsl}
`;

// The object's pelt structs (common.wgsl's Frame and Object): the fields the shared functions
// read.
const structsGlsl = /* glsl */ `
uniform vec4 peltWind;
uniform vec4 peltGust;
uniform float furLength;
Frame pelt_frame() {
  Frame f;
  f.view = viewMatrix;
  f.proj = projectionMatrix;
  f.wind = peltWind;
  f.gust = peltGust;
  return f;
}
Object pelt_object() {
  Object o;
  o.model = modelMatrix;
  o.normal_model = transpose(inverse(modelMatrix));
  o.fur_base = vec4(0.0, 0.0, 0.0, furLength);
  return o;
}
`;

// The fur vertex attributes and their decode (docs/extension/PELT_fur: the comb is stored
// unsigned-normalized as (x + 1) / 2, or as is).
const furVertexHead = /* glsl */ `
#include <common>
#include <skinning_pars_vertex>
#include <shadowmap_pars_vertex>
${peltGlsl}
${structsGlsl}
attribute vec4 tangent;
attribute vec4 _fur_comb;
uniform vec3 albedo;
uniform float combUnsigned;
vec4 pelt_comb() {
  vec4 c = _fur_comb;
  if (combUnsigned > 0.5) c.xyz = c.xyz * 2.0 - 1.0;
  return c;
}
`;

// The skinned normal, tangent and position (three's skinning chunks).
const skinGlsl = /* glsl */ `
  vec3 objectNormal = normal;
  vec3 objectTangent = tangent.xyz;
  vec3 transformed = position;
#ifdef USE_SKINNING
  #include <skinbase_vertex>
  #include <skinnormal_vertex>
  objectTangent = (skinMatrix * vec4(objectTangent, 0.0)).xyz;
  #include <skinning_vertex>
#endif
`;

/** The shells (shells.wgsl's vs_main and fs_main with forward lighting and the medium). */
export const shellVertex = /* glsl */ `
${furVertexHead}
#ifdef PELT_DEPTH
#undef USE_SHADOWMAP
#endif
uniform float shells;
uniform float baseOnly;
out vec3 vViewPos;
out vec3 vStrand;
out vec4 vDepths;
out vec2 vUv;
out vec3 vAlbedo;
out vec4 vLayer;
out vec3 vViewNormal;
flat out float vShell;
void main() {
  ${skinGlsl}
  Frame frame = pelt_frame();
  Object object = pelt_object();
  vec4 fc = pelt_comb();
  float shell = baseOnly > 0.5 ? 0.0 : float(gl_InstanceID + 1);
  float n = max(shells, 1.0);
  float z0 = max(shell - 1.0, 0.0) / n;
  float z1 = shell / n;
  float sd = shell == 0.0 ? 0.0 : 0.5 * (z0 + z1);
  vec3 comb = wind_comb(comb_object(objectNormal, vec4(objectTangent, tangent.w), fc.xyz), objectNormal, transformed, frame, object);
  float cl = fc.w;
  mat4 toView = viewMatrix * modelMatrix;
  vec4 p = toView * vec4(transformed + shell_offset(objectNormal, comb, sd, furLength, cl), 1.0);
  vec4 pb = toView * vec4(transformed, 1.0);
  vec4 pt = toView * vec4(transformed + shell_offset(objectNormal, comb, 1.0, furLength, cl), 1.0);
  vec4 p0 = toView * vec4(transformed + shell_offset(objectNormal, comb, z0, furLength, cl), 1.0);
  vec4 p1 = toView * vec4(transformed + shell_offset(objectNormal, comb, z1, furLength, cl), 1.0);
  gl_Position = projectionMatrix * p;
  vViewPos = p.xyz;
  vStrand = view_dir_of(strand_tangent(objectNormal, comb, sd), frame, object);
  vDepths = vec4(-pb.z, -pt.z, sd, fc.w);
  vUv = uv;
  vAlbedo = albedo;
  vLayer = vec4(z0, z1, length(p1.xyz - p0.xyz), length(pt.xyz - pb.xyz));
  vViewNormal = view_normal_of(objectNormal, frame, object);
  vShell = shell;
#if defined( USE_SHADOWMAP ) && !defined( PELT_DEPTH )
  vec4 worldPosition = modelMatrix * vec4(transformed + shell_offset(objectNormal, comb, sd, furLength, cl), 1.0);
  vec3 transformedNormal = normalMatrix * objectNormal;
  #include <shadowmap_vertex>
#endif
}
`;

// The shells' opacity (shells.wgsl's coverage_of with the medium): its uniforms, the shell
// varyings and pelt_coverage().
const coverageGlsl = /* glsl */ `
uniform sampler2D densityLo;
uniform sampler2D densityHi;
uniform sampler2D baseMap;
uniform float useBaseMap;
uniform mat3 baseMapTransform;
uniform float colorFromTexture;
uniform vec3 tint;
uniform vec3 rootColor;
uniform vec3 tipColor;
uniform float uvScale;
uniform float kappa;
// A negative control for the tests: every shell opaque (no coverage).
uniform float controlOpaque;
in vec3 vViewPos;
in vec3 vStrand;
in vec4 vDepths;
in vec2 vUv;
in vec3 vAlbedo;
in vec4 vLayer;
in vec3 vViewNormal;
flat in float vShell;
float pelt_coverage() {
  if (vShell == 0.0 || controlOpaque > 0.5) return 1.0;
  vec2 tuv = vUv * uvScale;
  vec2 uvDx = dFdx(tuv);
  vec2 uvDy = dFdy(tuv);
  vec3 pDx = dFdx(vViewPos);
  vec3 pDy = dFdy(vViewPos);
  vec4 lo = textureGrad(densityLo, tuv, 0.5 * uvDx, 0.5 * uvDy);
  vec4 hi = textureGrad(densityHi, tuv, 0.5 * uvDx, 0.5 * uvDy);
  float surfaceArea = length(cross(pDx, pDy));
  float tileArea = abs(uvDx.x * uvDy.y - uvDx.y * uvDy.x);
  vec3 eye = isOrthographic ? vec3(0.0, 0.0, 1.0) : normalize(-vViewPos);
  float mu = max(abs(dot(normalize(vViewNormal), eye)), MIN_COS);
  float vt = dot(eye, normalize(vStrand));
  float sinPsi = sqrt(max(1.0 - vt * vt, 0.0));
  float sqrtJ = sqrt(tileArea / max(surfaceArea, 1e-20));
  float a = clamp(layer_opacity(lo, hi, vLayer.x, vLayer.y, kappa, sinPsi, vLayer.z * sqrtJ, mu), 0.0, 1.0);
  return a * clamp(vDepths.w * 20.0, 0.0, 1.0);
}
`;

export const shellFragment = /* glsl */ `
${fragmentHead}
${furLightingGlsl}
${coverageGlsl}
void main() {
  float a = pelt_coverage();
  if (a <= 0.0) discard;
  vec3 under = useBaseMap > 0.5 ? texture(baseMap, (baseMapTransform * vec3(vUv, 1.0)).xy).rgb : vec3(1.0);
  vec3 diffuse;
  vec3 specular;
  pelt_fur_lighting(vViewPos, normalize(vStrand), diffuse, specular);
  vec3 t = colorFromTexture > 0.5 ? under : vec3(1.0);
  vec3 albedo = vAlbedo * tint * t * mix(rootColor, tipColor, vDepths.z);
  gl_FragColor = vec4(albedo * diffuse + ${SPECULAR_STRENGTH.toFixed(2)} * specular, a);
}
`;

/**
 * The shells from a shadow-casting light (three's shadow pass: depth only): each fragment is
 * kept with the probability of its layer's opacity (a hashed alpha test), so a texel of the
 * map is lit through the fur with the probability ∏(1 − αᵢ), the layers' transmittance, which
 * the map's filtering averages: the fur casts by its coverage.
 */
export const shellDepthFragment = /* glsl */ `
#include <common>
${peltGlsl}
${coverageGlsl}
float pelt_hash(vec3 p) {
  p = fract(p * vec3(0.1031, 0.1030, 0.0973));
  p += dot(p, p.yxz + 33.33);
  return fract((p.x + p.y) * p.z);
}
void main() {
  float a = pelt_coverage();
  if (a <= pelt_hash(vec3(gl_FragCoord.xy, vShell))) discard;
  gl_FragColor = vec4(1.0);
}
`;

/**
 * The fins (fins.wgsl): one instance per fin edge, six vertices of a quad from the edge at
 * the root to the edge pushed out along the combed path at the tip; `p0`… are the edge's
 * vertices, normals, object-space combs (w the comb length) and face normals, in the mesh's
 * space (posed on the CPU for skinned meshes).
 */
export const finVertex = /* glsl */ `
#include <common>
#include <shadowmap_pars_vertex>
${peltGlsl}
${structsGlsl}
attribute vec3 p0;
attribute vec3 p1;
attribute vec3 n0;
attribute vec3 n1;
attribute vec4 t0;
attribute vec4 t1;
attribute vec4 c0;
attribute vec4 c1;
attribute vec3 f0;
attribute vec3 f1;
attribute vec2 fu;
attribute vec2 fuv;
uniform vec3 albedo;
uniform sampler2D baseMap;
uniform float useBaseMap;
uniform mat3 baseMapTransform;
uniform float analytic;
uniform float uvScale;
uniform float colorFromTexture;
out vec3 vViewPos;
out vec3 vStrand;
out vec4 vDepths;
out vec2 vUv;
flat out vec3 vUnder;
float fin_fade(mat4 toView, vec4 k0, vec4 k1, Frame frame, Object object) {
  vec4 mid = toView * vec4(0.5 * (p0 + p1), 1.0);
  vec3 toEye = normalize(-mid.xyz);
  float s0 = dot(view_normal_of(f0, frame, object), toEye);
  float s1 = dot(view_normal_of(f1, frame, object), toEye);
  vec3 edge = view_dir_of(p1 - p0, frame, object);
  vec3 up = view_dir_of(normalize(n0 + n1) + 0.5 * (k0.xyz + k1.xyz), frame, object);
  vec3 finNormal = cross(edge, up);
  float len = length(finNormal);
  float faceOn = len > 1e-6 ? abs(dot(finNormal / len, toEye)) : 0.0;
  float hasFur = max(k0.w, k1.w) > 0.0 ? 1.0 : 0.0;
  return fin_visibility(s0, s1, faceOn, analytic > 0.5) * hasFur;
}
void main() {
  Frame frame = pelt_frame();
  Object object = pelt_object();
  mat4 toView = viewMatrix * modelMatrix;
  // The object-space combs (comb_object: the tangent-space comb in the edge's frames).
  vec4 k0 = vec4(comb_object(n0, t0, c0.xyz), c0.w);
  vec4 k1 = vec4(comb_object(n1, t1, c1.xyz), c1.w);
  float fade = fin_fade(toView, k0, k1, frame, object);
  if (fade < 1e-3) {
    gl_Position = vec4(0.0, 0.0, -1.0, 1.0);
    return;
  }
  int vi = gl_VertexID % 6;
  int e = (vi == 1 || vi == 2 || vi == 4) ? 1 : 0;
  float t = (vi == 2 || vi == 4 || vi == 5) ? 1.0 : 0.0;
  vec3 p = e == 1 ? p1 : p0;
  vec3 n = e == 1 ? n1 : n0;
  vec4 cc = e == 1 ? k1 : k0;
  vec4 c = vec4(wind_comb(cc.xyz, n, p, frame, object), cc.w);
  vec4 pv = toView * vec4(p + shell_offset(n, c.xyz, t, furLength, c.w), 1.0);
  vec4 pb = toView * vec4(p, 1.0);
  vec4 pt = toView * vec4(p + shell_offset(n, c.xyz, 1.0, furLength, c.w), 1.0);
  gl_Position = projectionMatrix * pv;
  vViewPos = pv.xyz;
  vStrand = view_dir_of(strand_tangent(n, c.xyz, t), frame, object);
  vDepths = vec4(-pb.z, -pt.z, t, fade);
  vUv = vec2(fu.x + float(e) * fu.y * uvScale, 1.0 - t);
  vec3 under = albedo * (useBaseMap > 0.5 ? textureLod(baseMap, (baseMapTransform * vec3(fuv, 1.0)).xy, 0.0).rgb : vec3(1.0));
  vUnder = colorFromTexture > 0.5 ? under : vec3(1.0);
#ifdef USE_SHADOWMAP
  vec4 worldPosition = modelMatrix * vec4(p + shell_offset(n, c.xyz, t, furLength, c.w), 1.0);
  vec3 transformedNormal = normalMatrix * n;
  #include <shadowmap_vertex>
#endif
}
`;

export const finFragment = /* glsl */ `
${fragmentHead}
${furLightingGlsl}
uniform sampler2D finMap;
uniform vec3 tint;
uniform vec3 rootColor;
uniform vec3 tipColor;
in vec3 vViewPos;
in vec3 vStrand;
in vec4 vDepths;
in vec2 vUv;
flat in vec3 vUnder;
void main() {
  vec4 tex = texture(finMap, vUv);
  vec3 diffuse;
  vec3 specular;
  pelt_fur_lighting(vViewPos, normalize(vStrand), diffuse, specular);
  vec3 albedo = tint * vUnder * mix(rootColor, tipColor, tex.r);
  float a = tex.a * vDepths.w;
  if (a <= 0.002) discard;
  gl_FragColor = vec4(albedo * diffuse + ${SPECULAR_STRENGTH.toFixed(2)} * specular, a);
}
`;

/** pelt's forward opaque surface (forward.wgsl): Blinn-Phong per light, metal_rough. */
export const surfaceVertex = /* glsl */ `
#include <common>
#include <skinning_pars_vertex>
#include <shadowmap_pars_vertex>
out vec3 vViewPos;
out vec3 vViewNormal;
out vec2 vUv;
void main() {
  vec3 objectNormal = normal;
  vec3 transformed = position;
#ifdef USE_SKINNING
  #include <skinbase_vertex>
  #include <skinnormal_vertex>
  #include <skinning_vertex>
#endif
  vec4 view = viewMatrix * modelMatrix * vec4(transformed, 1.0);
  gl_Position = projectionMatrix * view;
  vViewPos = view.xyz;
  vViewNormal = (viewMatrix * vec4((transpose(inverse(modelMatrix)) * vec4(objectNormal, 0.0)).xyz, 0.0)).xyz;
  vUv = uv;
#ifdef USE_SHADOWMAP
  vec4 worldPosition = modelMatrix * vec4(transformed, 1.0);
  vec3 transformedNormal = normalMatrix * objectNormal;
  #include <shadowmap_vertex>
#endif
}
`;

export const surfaceFragment = /* glsl */ `
${fragmentHead}
uniform vec4 albedo;
uniform sampler2D baseMap;
uniform float useBaseMap;
uniform mat3 baseMapTransform;
uniform float metallic;
uniform float roughness;
uniform float opacity;
in vec3 vViewPos;
in vec3 vViewNormal;
in vec2 vUv;
void main() {
  vec4 base = useBaseMap > 0.5 ? texture(baseMap, (baseMapTransform * vec3(vUv, 1.0)).xy) : vec4(1.0);
  vec3 n = facing_normal(vViewNormal, gl_FrontFacing);
  vec4 a = albedo * base;
  vec3 diffuse = ambientLightColor;
  vec3 specular = vec3(0.0);
  vec3 p = vViewPos;
${lightLoop('one_light(p, n, r, l, ' + SPECULAR_POWER.toFixed(1) + ')')}
  vec2 k = metal_rough(metallic, roughness);
  vec3 specTint = mix(vec3(1.0), a.rgb, metallic);
  gl_FragColor = vec4(a.rgb * k.y * diffuse + ${SPECULAR_STRENGTH.toFixed(2)} * k.x * specTint * specular, opacity * a.a);
}
`;

/** The procedural sky (sky.wgsl) on a full-screen triangle at the far plane. */
export const skyVertex = /* glsl */ `
out vec2 vNdc;
void main() {
  vNdc = position.xy;
  gl_Position = vec4(position.xy, 1.0, 1.0);
}
`;

export const skyFragment = /* glsl */ `
${peltGlsl}
uniform mat4 peltCameraWorld;
uniform vec2 peltTanHalf;
in vec2 vNdc;
void main() {
  vec3 v = normalize(vec3(vNdc.x * peltTanHalf.x, vNdc.y * peltTanHalf.y, -1.0));
  vec3 d = normalize(mat3(peltCameraWorld) * v);
  gl_FragColor = vec4(procedural(d), 1.0);
}
`;

/** Linear HDR image to the canvas, sRGB-encoded (what pelt's Rgba8UnormSrgb target does). */
export const outputVertex = skyVertex;
export const outputFragment = /* glsl */ `
uniform sampler2D image;
in vec2 vNdc;
vec3 srgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main() {
  vec4 c = texture(image, vNdc * 0.5 + 0.5);
  gl_FragColor = vec4(srgb(c.rgb), 1.0);
}
`;
