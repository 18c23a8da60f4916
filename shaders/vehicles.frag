#version 300 es
// The traffic: models lit as the untextured surfaces (shaders/untextured.glsl: a hemisphere light
// from sky and ground plus the sun, up = z), and a contact shadow fading at its edges. Depth: the
// rasteriser's own, tested against the view's depth rewritten in that encoding
// (vehicle_depth.frag), so that the geometry in front of a vehicle hides it (the 2013 paper, §3:
// composited with the Z-buffer) and hidden fragments are rejected before they are shaded.
precision highp float;
uniform vec3 u_sunDir;  // towards the sun, unit
uniform vec3 u_skyLight;
uniform vec3 u_groundLight;
uniform vec3 u_sunLight;
uniform float u_shadowOpacity;
uniform float u_shadow;  // 1: the contact-shadow quad
in vec3 v_normal;
in vec3 v_colour;
in vec2 v_shadowUv;
out vec4 o_color;
void main() {
  if (u_shadow > 0.5) {
    float edge = max(abs(v_shadowUv.x), abs(v_shadowUv.y));
    o_color = vec4(0.0, 0.0, 0.0, u_shadowOpacity * (1.0 - smoothstep(0.7, 1.0, edge)));
    return;
  }
  vec3 n = normalize(v_normal);
  vec3 ambient = mix(u_groundLight, u_skyLight, 0.5 * (1.0 + n.z));
  o_color = vec4(clamp(v_colour * (ambient + u_sunLight * max(0.0, dot(n, u_sunDir))), 0.0, 1.0), 1.0);
}
