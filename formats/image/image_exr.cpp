#include <algorithm>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <ImfThreading.h>

#include "formats/core/file_util.h"
#include "formats/image/image.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

Imf::PixelType pixelType(SampleType t, const std::string& path) {
  switch (t) {
    case SampleType::U32: return Imf::UINT;
    case SampleType::F16: return Imf::HALF;
    case SampleType::F32: return Imf::FLOAT;
    default: throw Error(ErrorKind::Internal, path + ": EXR holds uint32, half or float samples");
  }
}

const char* const kChannelNames[4] = {"R", "G", "B", "A"};

}  // namespace

namespace {

/// OpenEXR's worker pool is process-wide and starts empty: grow it (only
/// ever grow it, under a lock) so that a writer asking for `threads` finds them.
void ensureExrWorkers(unsigned threads) {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  if (Imf::globalThreadCount() < int(threads)) Imf::setGlobalThreadCount(int(threads));
}

}  // namespace

void writeExr(const Image& image, const std::string& path, ExrCompression compression, unsigned threads) {
  const Imf::PixelType type = pixelType(image.type, path);
  if (image.channels < 1 || image.channels > 4 || image.width == 0 || image.height == 0)
    throw Error(ErrorKind::Internal, path + ": bad image shape for EXR");
  const Imf::Compression c[] = {Imf::NO_COMPRESSION, Imf::ZIP_COMPRESSION, Imf::ZIPS_COMPRESSION,
                                Imf::PIZ_COMPRESSION, Imf::RLE_COMPRESSION};
  try {
    Imf::Header header(int(image.width), int(image.height));
    header.compression() = c[int(compression)];
    for (uint32_t ch = 0; ch < image.channels; ++ch) header.channels().insert(kChannelNames[ch], Imf::Channel(type));
    for (const auto& [k, v] : image.text) header.insert(k, Imf::StringAttribute(v));
    Imf::FrameBuffer fb;
    const size_t sb = sampleBytes(image.type);
    for (uint32_t ch = 0; ch < image.channels; ++ch)
      fb.insert(kChannelNames[ch],
                Imf::Slice(type, reinterpret_cast<char*>(const_cast<uint8_t*>(image.pixels.data())) + ch * sb,
                           image.channels * sb, image.rowBytes()));
    if (threads > 1) ensureExrWorkers(threads);
    Imf::OutputFile out(path.c_str(), header, threads > 1 ? int(threads) : 0);
    out.setFrameBuffer(fb);
    out.writePixels(int(image.height));
  } catch (const std::exception& e) {
    throwIo(path + ": EXR write failed: " + e.what());
  }
}

/// The first header attribute whose size runs past the end of the file, as a
/// message ("" when the header's attributes fit). OpenEXR allocates an
/// attribute at the size the file gives before reading it: a 1 KB render
/// whose string attribute claimed 1.8 GB took 1.8 GB and 3.4 s before "Early
/// end of file". Walks every header of a multi-part file; anything else
/// malformed is left for OpenEXR to report.
static std::string attributePastEnd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const uint64_t total = std::filesystem::file_size(path);
  char version[8];
  if (!in.read(version, 8)) return {};
  const bool multipart = (uint8_t(version[5]) & 0x10) != 0;  // version flags bit 12
  auto cstring = [&](std::string& out) {
    out.clear();
    for (char c; in.get(c);) {
      if (c == 0) return true;
      if (out.size() >= 255) return false;
      out += c;
    }
    return false;
  };
  std::string name, type;
  for (;;) {
    if (!cstring(name)) return {};
    if (name.empty()) {  // end of a header; a multi-part file's list ends with an empty header
      if (!multipart || in.peek() == 0) return {};
      continue;
    }
    int32_t size = 0;
    if (!cstring(type) || !in.read(reinterpret_cast<char*>(&size), 4)) return {};
    const uint64_t at = uint64_t(in.tellg());
    if (size < 0 || uint64_t(size) > total - std::min(total, at))
      return "header attribute '" + name + "' (" + type + ") at byte " + std::to_string(at) + " claims " +
             std::to_string(size) + " bytes, more than the " + std::to_string(total - std::min(total, at)) +
             " left in the file";
    if (!in.seekg(std::streamoff(at + uint64_t(size)))) return {};
  }
}

Image readExr(const std::string& path) {
  requireRegularFile(path);
  if (!isExrFile(path)) throwBadInput(path + ": not an OpenEXR file (wrong magic number or unreadable)");
  if (const std::string why = attributePastEnd(path); !why.empty())
    throwBadInput(path + ": corrupt or truncated EXR: " + why);
  Image image;
  try {
    Imf::InputFile in(path.c_str());
    const Imf::Header& h = in.header();
    const Imath::Box2i dw = h.dataWindow();
    image.width = uint32_t(dw.max.x - dw.min.x + 1);
    image.height = uint32_t(dw.max.y - dw.min.y + 1);
    image.channels = 0;
    Imf::PixelType type = Imf::HALF;
    for (uint32_t ch = 0; ch < 4; ++ch) {
      const Imf::Channel* c = h.channels().findChannel(kChannelNames[ch]);
      if (!c) break;
      if (ch == 0) type = c->type;
      else if (c->type != type) throwBadInput(path + ": channels of different types are not supported");
      ++image.channels;
    }
    if (image.channels == 0) throwBadInput(path + ": no R channel");
    image.type = type == Imf::UINT ? SampleType::U32 : type == Imf::HALF ? SampleType::F16 : SampleType::F32;
    // A data window its file could not hold compressed is refused before its
    // pixels are allocated: a 1 KB render edited to claim 16777216 x 6 pixels
    // was read as an image (0.43 GB, 2.6 s). No EXR compression expands more
    // than 2^17:1 (deflate 1032:1, RLE 64:1, PIZ's run codes about 300:1,
    // DWA's run-length then deflate stages below 2^17 together).
    const uint64_t decoded = uint64_t(image.rowBytes()) * image.height;
    const uint64_t fileBytes = std::filesystem::file_size(path);
    if (decoded > (fileBytes + 1) << 17)
      throwBadInput(path + ": corrupt or truncated EXR: its data window is " + std::to_string(image.width) + " x " +
                    std::to_string(image.height) + " pixels (" + std::to_string(decoded) + " bytes), more than its " +
                    std::to_string(fileBytes) + " bytes can hold compressed");
    image.pixels.assign(image.rowBytes() * image.height, 0);
    const size_t sb = sampleBytes(image.type);
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(image.pixels.data()) -
                 (size_t(dw.min.x) * image.channels * sb + size_t(dw.min.y) * image.rowBytes());
    for (uint32_t ch = 0; ch < image.channels; ++ch)
      fb.insert(kChannelNames[ch], Imf::Slice(type, base + ch * sb, image.channels * sb, image.rowBytes()));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    for (auto it = h.begin(); it != h.end(); ++it)
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        image.text.emplace_back(it.name(), s->value());
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throwBadInput(path + ": corrupt or truncated EXR: " + e.what());
  }
  return image;
}

}  // namespace vox
