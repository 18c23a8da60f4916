// libFuzzer build only (HV_FUZZ=ON): stb_image compiled into fuzz_image_decode with coverage
// instrumentation and the sanitizers. The definitions in the executable take precedence over the
// system libstb.so that the image module links, so hv::decodeImage runs this copy (the same header) and the
// fuzzer gets coverage feedback from inside the decoders instead of fuzzing blind.
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
