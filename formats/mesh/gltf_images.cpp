#include "formats/mesh/gltf_images.h"

#include <tbb/parallel_for.h>
#include <tiny_gltf.h>

#include <cstring>

#include "formats/mesh/texture_image.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

bool keepEncoded(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                 const unsigned char* bytes, int size, void* user) {
  auto& images = *static_cast<EncodedImages*>(user);
  if (index < 0) return false;
  if (size_t(index) >= images.received.size()) images.resize(size_t(index) + 1);
  const size_t n = size_t(std::max(size, 0));
  if (image->bufferView >= 0) {  // `bytes` lies in the model's buffer, which outlives the load
    images.inModel[size_t(index)] = std::string_view(reinterpret_cast<const char*>(bytes), n);
    images.received[size_t(index)] = 2;
  } else {
    images.owned[size_t(index)].assign(reinterpret_cast<const char*>(bytes), n);
    images.received[size_t(index)] = 1;
  }
  image->width = image->height = image->component = image->bits = -1;  // not decoded (yet)
  return true;
}

struct Decoded {
  TextureImage image;
  std::string why;
  bool ok = false;
};

/// "model.glb: image 3 'wood.jpg'" (no uri for embedded images).
std::string imageName(const std::string& path, size_t index, const tinygltf::Image& im) {
  return path + ": image " + std::to_string(index) + (im.uri.empty() || im.uri.rfind("data:", 0) == 0 ? "" : " '" + im.uri + "'");
}

}  // namespace

void deferImageDecoding(tinygltf::TinyGLTF& loader, EncodedImages& images) { loader.SetImageLoader(&keepEncoded, &images); }

void decodeImages(tinygltf::Model& model, EncodedImages& images, const std::vector<char>& needed,
                  const std::string& path, const MeshReadOptions& options, std::vector<std::string>& warnings) {
  images.resize(model.images.size());
  std::vector<size_t> todo;
  for (size_t i = 0; i < needed.size() && i < model.images.size(); ++i)
    if (needed[i] && images.received[i]) todo.push_back(i);
  // One task per image: a large texture is decoded on one thread, several in parallel.
  std::vector<Decoded> out(todo.size());
  tbb::parallel_for(
      size_t(0), todo.size(),
      [&](size_t k) { out[k].ok = decodeTextureImage(images.bytes(todo[k]), out[k].image, out[k].why); },
      tbb::simple_partitioner());
  for (size_t k = 0; k < todo.size(); ++k) {
    tinygltf::Image& im = model.images[todo[k]];
    images.owned[todo[k]] = std::string();
    if (!out[k].ok) {
      const std::string what = imageName(path, todo[k], im) + " cannot be decoded (" + out[k].why + ")";
      if (options.ignoreMissingMaterials) {
        warnings.push_back(what + "; its textures are left out");
        continue;
      }
      throwUndecodableImage(imageName(path, todo[k], im), out[k].why);
    }
    if (!out[k].image.warning.empty())
      warnings.push_back(damagedImageWarning(imageName(path, todo[k], im), out[k].image.warning));
    im.width = int(out[k].image.width);
    im.height = int(out[k].image.height);
    im.component = 4;
    im.bits = 8;
    im.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    im.image = std::move(out[k].image.rgba);
  }
}

std::vector<int> decodeImagesLater(const std::shared_ptr<tinygltf::Model>& model, EncodedImages& images,
                                   const std::vector<char>& needed, const std::string& path, DeferredTextures& deferred) {
  const size_t n = model->images.size();
  images.resize(n);
  // The images stay in the model's buffers, which then live until the bake
  // has read them, when they are most of those buffers (a textured .glb);
  // when they are not (large geometry, small textures), their bytes are
  // copied and the buffers go when the read returns.
  uint64_t imageBytes = 0, bufferBytes = 0;
  for (size_t i = 0; i < needed.size() && i < n; ++i)
    if (needed[i] && images.isInModel(i)) imageBytes += images.bytes(i).size();
  for (const tinygltf::Buffer& b : model->buffers) bufferBytes += b.data.size();
  const bool keepModel = imageBytes * 2 >= bufferBytes;
  std::vector<int> jobOf(n, -1);
  for (size_t i = 0; i < needed.size() && i < n; ++i) {
    if (!needed[i] || !images.received[i]) continue;
    std::string name = imageName(path, i, model->images[i]);
    if (images.isInModel(i) && keepModel)
      jobOf[i] = int(deferred.addImage(model, images.bytes(i), std::move(name)));
    else if (images.isInModel(i))
      jobOf[i] = int(deferred.addImage(std::string(images.bytes(i)), std::move(name)));
    else
      jobOf[i] = int(deferred.addImage(std::move(images.owned[i]), std::move(name)));
  }
  return jobOf;
}

}  // namespace vox
