#version 300 es
// Debug lines: one colour, tested against the view's depth buffer with the linear depth that
// depth.frag stores (so a line behind a wall fails a GL_LESS test and passes a GL_GREATER one).
precision highp float;
uniform float u_near;
uniform float u_far;
uniform vec4 u_color;
out vec4 o_color;
void main() {
  gl_FragDepth = clamp((1.0 / gl_FragCoord.w - u_near) / (u_far - u_near), 0.0, 1.0);
  o_color = u_color;
}
