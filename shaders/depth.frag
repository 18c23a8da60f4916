#version 300 es
// Stores *linear* depth (distance along the camera axis) mapped to [0, 1] between near and far,
// so that the shadow bias is in scene units and the precision is uniform over the range
// (DESIGN.md §2 step 3). gl_FragCoord.w is 1 / clip w = 1 / z_camera.
precision highp float;
uniform float u_near;
uniform float u_far;
void main() { gl_FragDepth = clamp((1.0 / gl_FragCoord.w - u_near) / (u_far - u_near), 0.0, 1.0); }
