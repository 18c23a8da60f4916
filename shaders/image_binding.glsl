// Texture binding of the photographs and depth maps, included by ibr_shade.frag.
// HV_NAIVE: the baseline the papers improve on (Brédif 2013; de Castro & Brédif 2022 §2.1): one
// sampler2D per photograph and one per depth map, two texture units per image, up to
// HV_NAIVE_COUNT (<= 16) images; the renderer binds the i-th selected image to u_image<i> and
// u_depth<i>, and the shading loop is unrolled with one sampler pair per step (GLSL ES 3.00
// indexes sampler arrays only with constant expressions). Otherwise: one texture2DArray of each.
#ifdef HV_NAIVE
#if HV_NAIVE_COUNT > 0
uniform highp sampler2D u_image0;
uniform highp sampler2D u_depth0;
#endif
#if HV_NAIVE_COUNT > 1
uniform highp sampler2D u_image1;
uniform highp sampler2D u_depth1;
#endif
#if HV_NAIVE_COUNT > 2
uniform highp sampler2D u_image2;
uniform highp sampler2D u_depth2;
#endif
#if HV_NAIVE_COUNT > 3
uniform highp sampler2D u_image3;
uniform highp sampler2D u_depth3;
#endif
#if HV_NAIVE_COUNT > 4
uniform highp sampler2D u_image4;
uniform highp sampler2D u_depth4;
#endif
#if HV_NAIVE_COUNT > 5
uniform highp sampler2D u_image5;
uniform highp sampler2D u_depth5;
#endif
#if HV_NAIVE_COUNT > 6
uniform highp sampler2D u_image6;
uniform highp sampler2D u_depth6;
#endif
#if HV_NAIVE_COUNT > 7
uniform highp sampler2D u_image7;
uniform highp sampler2D u_depth7;
#endif
#if HV_NAIVE_COUNT > 8
uniform highp sampler2D u_image8;
uniform highp sampler2D u_depth8;
#endif
#if HV_NAIVE_COUNT > 9
uniform highp sampler2D u_image9;
uniform highp sampler2D u_depth9;
#endif
#if HV_NAIVE_COUNT > 10
uniform highp sampler2D u_image10;
uniform highp sampler2D u_depth10;
#endif
#if HV_NAIVE_COUNT > 11
uniform highp sampler2D u_image11;
uniform highp sampler2D u_depth11;
#endif
#if HV_NAIVE_COUNT > 12
uniform highp sampler2D u_image12;
uniform highp sampler2D u_depth12;
#endif
#if HV_NAIVE_COUNT > 13
uniform highp sampler2D u_image13;
uniform highp sampler2D u_depth13;
#endif
#if HV_NAIVE_COUNT > 14
uniform highp sampler2D u_image14;
uniform highp sampler2D u_depth14;
#endif
#if HV_NAIVE_COUNT > 15
uniform highp sampler2D u_image15;
uniform highp sampler2D u_depth15;
#endif
#else
uniform highp sampler2DArray u_images;     // premultiplied RGBA8, alpha = mask
uniform highp sampler2DArray u_depthMaps;  // linear depth in [0, 1] between near and far
#endif
