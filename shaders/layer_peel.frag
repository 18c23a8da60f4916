#version 300 es
// Visibility layers on the GPU (Layered projective texture maps, 2003, §4.1; the CPU reference is
// hv/layers/visibility_layers.h over the rays of hv/layers/native/scene_objects.h). Distances are
// along the ray from the camera centre, stored as float bits in 32-bit integer targets (exact in
// GLES 3.0 and WebGL2, where float colour targets need an extension). Three variants:
// - HV_PEEL_TERRAIN: the nearest terrain surface facing the camera (u_backFaces false) or facing
//   away (true), written to the channel the colour mask leaves open: where a ray enters the ground
//   and where it leaves it.
// - HV_PEEL_ITEM: the item buffer, object id + 1 and distance of the nearest surface of the
//   working set (with the depth test).
// - otherwise the occlusion test, one object per occlusion query: a fragment passes where the
//   item buffer holds another object nearer than it by more than the ray caster's same-surface
//   tolerance: the object is behind another one of the working set there (the paper's inverted
//   depth test). With u_anyFragment, every kept fragment passes (is the object seen at all).
// Every variant keeps only surfaces facing the camera; the others only those not under the ground
// (between where the ray enters the terrain and where it leaves it), as the ray caster does.
precision highp float;
precision highp int;
precision highp usampler2D;
uniform vec3 u_center;  // the camera centre, render frame
in vec3 v_position;
flat in vec3 v_normal;
flat in uint v_object;

#ifdef HV_PEEL_TERRAIN
uniform bool u_backFaces;
out uvec4 o_value;
void main() {
  vec3 ray = v_position - u_center;
  if ((dot(v_normal, ray) < 0.0) == u_backFaces) discard;
  uint bits = floatBitsToUint(length(ray));
  o_value = uvec4(bits, bits, 0u, 0u);
}
#else
uniform usampler2D u_working;  // per object, at (id % width, id / width): 1 while in the working set
uniform int u_workingWidth;
uniform usampler2D u_terrain;  // r: where the ray enters the ground, g: where it leaves it
uniform vec2 u_sameSurface;    // metres, fraction of the distance
#ifdef HV_PEEL_ITEM
out uvec4 o_item;
#else
uniform usampler2D u_item;
uniform bool u_anyFragment;
#endif

float tolerance(float d) { return u_sameSurface.x + u_sameSurface.y * d; }

void main() {
  vec3 ray = v_position - u_center;
  if (dot(v_normal, ray) >= 0.0) discard;
  uint id = v_object & 0x7fffffffu;
  int w = max(u_workingWidth, 1);
  if (texelFetch(u_working, ivec2(int(id) % w, int(id) / w), 0).r == 0u) discard;
  float d = length(ray);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  if ((v_object & 0x80000000u) == 0u) {
    uvec2 ground = texelFetch(u_terrain, pixel, 0).rg;
    float enters = uintBitsToFloat(ground.r), leaves = uintBitsToFloat(ground.g);
    if (d > enters + tolerance(enters) && d < leaves) discard;
  }
#ifdef HV_PEEL_ITEM
  o_item = uvec4(id + 1u, floatBitsToUint(d), 0u, 0u);
#else
  if (!u_anyFragment) {
    uvec2 front = texelFetch(u_item, pixel, 0).rg;
    if (front.r == 0u || front.r == id + 1u) discard;
    float frontDistance = uintBitsToFloat(front.g);
    if (d <= frontDistance + tolerance(frontDistance)) discard;
  }
#endif
}
#endif
