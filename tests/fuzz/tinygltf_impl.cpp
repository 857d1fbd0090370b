// tinygltf's implementation compiled into the glTF fuzz target, so that the
// fuzzer sees (and the sanitizers check) the container parser too; the vox
// build links the packaged libtinygltf instead. stb_image comes from libstb.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
