#include "formats/mesh/deferred_textures.h"

#include <algorithm>
#include <chrono>
#include <functional>

#include "formats/mesh/texture_image.h"
#include "libvox/core/error.h"

namespace vox {

struct DeferredTextures::Image {
  std::string owned;                 // the encoded bytes when they were handed over
  std::shared_ptr<const void> owner;  // or what keeps them alive where they are
  std::string_view bytes;            // the encoded bytes, in `owned` or `owner`'s memory
  std::string name;
  std::vector<size_t> textures;  // the mesh textures whose pixels it is
  uint32_t width = 0, height = 0;  // from the header (0: it does not read)
  uint64_t decoderBytes = 0;       // textureDecoderBytes
  bool opened = false;             // a reader was opened for it
  std::string error;               // why it did not decode ("" while it did)
  std::string warning;             // TextureImage::warning once read
  double seconds = 0;              // decoding, on the threads that read it
};

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

class DeferredTextures::Reader final : public TextureRowReader {
 public:
  explicit Reader(Image& image) : image_(image) {}
  void start() { run([&](std::string& why) { return decoder_.open(image_.bytes, why); }); }
  uint32_t width() const override { return decoder_.width(); }
  uint32_t height() const override { return decoder_.height(); }
  void read(uint8_t* rgba, uint32_t count) override {
    run([&](std::string& why) { return decoder_.read(rgba, count, why); });
    if (image_.warning.empty()) image_.warning = decoder_.warning();
    if (decoder_.rowsRead() == decoder_.height()) {  // read to its end: its bytes are no longer needed
      image_.bytes = {};
      image_.owned = std::string();
      image_.owner.reset();
    }
  }

 private:
  void run(const std::function<bool(std::string&)>& step) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string why;
    const bool ok = step(why);
    image_.seconds += secondsSince(t0);
    if (ok) return;
    image_.error = why;
    throwUndecodableImage(image_.name, why);
  }
  Image& image_;
  TextureRowDecoder decoder_;
};

DeferredTextures::DeferredTextures() = default;
DeferredTextures::~DeferredTextures() = default;

size_t DeferredTextures::addImage(std::string bytes, std::string name) {
  auto image = std::make_unique<Image>();
  image->owned = std::move(bytes);
  image->bytes = image->owned;  // the Image never moves (held by pointer)
  image->name = std::move(name);
  return add(std::move(image));
}

size_t DeferredTextures::addImage(std::shared_ptr<const void> owner, std::string_view bytes, std::string name) {
  auto image = std::make_unique<Image>();
  image->owner = std::move(owner);
  image->bytes = bytes;
  image->name = std::move(name);
  return add(std::move(image));
}

size_t DeferredTextures::add(std::unique_ptr<Image> image) {
  if (!textureImageSize(image->bytes, image->width, image->height)) image->width = image->height = 0;
  image->decoderBytes = textureDecoderBytes(image->bytes);
  images_.push_back(std::move(image));
  return images_.size() - 1;
}

void DeferredTextures::addTexture(size_t image, size_t meshTexture) { images_[image]->textures.push_back(meshTexture); }

size_t DeferredTextures::images() const { return images_.size(); }

const std::vector<size_t>& DeferredTextures::texturesOf(size_t image) const { return images_[image]->textures; }

std::array<uint32_t, 2> DeferredTextures::size(size_t image) const {
  return {images_[image]->width, images_[image]->height};
}

std::unique_ptr<TextureRowReader> DeferredTextures::open(size_t image) {
  Image& im = *images_[image];
  if (im.opened) throw Error(ErrorKind::Internal, "texture image " + std::to_string(image) + " opened twice");
  im.opened = true;
  auto reader = std::make_unique<Reader>(im);
  reader->start();
  return reader;
}

void DeferredTextures::finish() {
  for (const std::unique_ptr<Image>& im : images_) {
    if (im->opened) continue;
    // Read through a few rows at a time, as the bake would have.
    std::unique_ptr<TextureRowReader> reader;
    try {
      reader = open(size_t(&im - images_.data()));
      std::vector<uint8_t> rows(size_t(reader->width()) * 4 * kTextureBandRows);
      for (uint32_t y = 0; y < reader->height(); y += kTextureBandRows)
        reader->read(rows.data(), std::min(kTextureBandRows, reader->height() - y));
    } catch (const Error&) {
      // Its error is thrown below, in index order with the others.
    }
  }
  for (const std::unique_ptr<Image>& im : images_)
    if (!im->error.empty()) throwUndecodableImage(im->name, im->error);
}

uint64_t DeferredTextures::readingBytes(unsigned threads) const {
  std::vector<uint64_t> each;
  for (const std::unique_ptr<Image>& im : images_) {
    // The bake's band, the row after it and row 0, and the decoder's own.
    each.push_back(uint64_t(im->width) * 4 * (kTextureBandRows + 2) + im->decoderBytes);
  }
  std::sort(each.rbegin(), each.rend());
  uint64_t bytes = 0;
  for (size_t i = 0; i < each.size() && i < std::max(threads, 1u); ++i) bytes += each[i];
  return bytes;
}

std::vector<std::string> DeferredTextures::warnings() const {
  std::vector<std::string> out;
  for (const std::unique_ptr<Image>& im : images_)
    if (!im->warning.empty()) out.push_back(damagedImageWarning(im->name, im->warning));
  return out;
}

size_t DeferredTextures::decodedImages() const {
  size_t n = 0;
  for (const std::unique_ptr<Image>& im : images_) n += im->opened;
  return n;
}

double DeferredTextures::decodeSeconds() const {
  double sum = 0;
  for (const std::unique_ptr<Image>& im : images_) sum += im->seconds;
  return sum;
}

}  // namespace vox
