// The debug views' colour ramp, twin of hv::colorRamp (src/hv/image/colormap.cpp; the same control
// points, evenly spaced in t): dark purple (0) through blue and green to yellow (1).
vec3 hv_colorRamp(float t) {
  const vec3 c0 = vec3(0.27, 0.00, 0.33);
  const vec3 c1 = vec3(0.23, 0.32, 0.55);
  const vec3 c2 = vec3(0.13, 0.57, 0.55);
  const vec3 c3 = vec3(0.37, 0.79, 0.38);
  const vec3 c4 = vec3(0.99, 0.91, 0.14);
  float s = clamp(t, 0.0, 1.0) * 4.0;
  int i = min(int(s), 3);
  float f = s - float(i);
  vec3 a = i == 0 ? c0 : i == 1 ? c1 : i == 2 ? c2 : c3;
  vec3 b = i == 0 ? c1 : i == 1 ? c2 : i == 2 ? c3 : c4;
  return mix(a, b, f);
}
