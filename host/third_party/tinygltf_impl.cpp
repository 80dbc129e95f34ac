// tinygltf (and the stb_image decoders it calls) compiled from their headers into hrpp_core, so
// that the sanitizers and libFuzzer's coverage instrumentation see the parser as well as our
// loader. Only the "asan" preset builds this (HRPP_TINYGLTF_FROM_HEADER, on with HRPP_FUZZ);
// every other build links Debian's libtinygltf.so, which is the same header compiled by Debian.
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>
