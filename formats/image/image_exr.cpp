#include <libdeflate.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <memory>
#include <mutex>
#include <vector>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfPartType.h>
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

std::string joinNames(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "none" : s;
}

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

/// The bytes OpenEXR 3.1 reads for an attribute of a fixed-size type (0 for
/// the others). It reads these whatever size the file declares, so a wrong
/// size puts its parse and any walk that trusts sizes at different places.
static uint32_t fixedAttributeBytes(const std::string& type) {
  static const std::pair<const char*, uint32_t> kSizes[] = {
      {"box2i", 16},  {"box2f", 16},  {"compression", 1}, {"lineOrder", 1}, {"envmap", 1},
      {"deepImageState", 1}, {"float", 4}, {"double", 8}, {"int", 4}, {"v2i", 8}, {"v2f", 8}, {"v2d", 16},
      {"v3i", 12},    {"v3f", 12},    {"v3d", 24},      {"m33f", 36},    {"m33d", 72}, {"m44f", 64},
      {"m44d", 128},  {"chromaticities", 32}, {"keycode", 28}, {"timecode", 8}, {"rational", 8},
      {"tiledesc", 9}};
  for (const auto& [name, bytes] : kSizes)
    if (type == name) return bytes;
  return 0;
}

/// Why a header cannot be handed to OpenEXR, as a message ("" when it can).
/// OpenEXR allocates what a header claims before reading it: an attribute at
/// its declared size (a 1 KB render whose string attribute claimed 1.8 GB
/// took 1.8 GB and 3.4 s before "Early end of file"), each string of a
/// stringvector, a preview at width x height. So every header of the file is
/// walked the way OpenEXR reads it, and refused when an attribute runs past the
/// end of the file, a fixed-size attribute declares another size (OpenEXR
/// would read it at its own size and parse the rest of the header from a
/// different place: how a fuzzer reached a 1.6 GB allocation), a channel list
/// or stringvector does not fill its attribute exactly, or a preview's
/// pixels are not its size. Valid files never do either.
static std::string headerProblem(const char* bytes, uint64_t total) {
  if (total < 8) return {};
  const bool multipart = (uint8_t(bytes[5]) & 0x10) != 0;  // version flags bit 12
  uint64_t at = 8;
  auto cstring = [&](std::string& out, uint64_t end) {
    out.clear();
    while (at < end) {
      const char c = bytes[at++];
      if (c == 0) return true;
      if (out.size() >= 255) return false;
      out += c;
    }
    return false;
  };
  auto int32At = [&](uint64_t where) {
    int32_t v = 0;
    std::memcpy(&v, bytes + where, 4);
    return v;
  };
  std::string name, type, channel;
  for (;;) {
    if (!cstring(name, total)) return {};
    if (name.empty()) {  // end of a header; a multi-part file's list ends with an empty header
      if (!multipart || at >= total || bytes[at] == 0) return {};
      continue;
    }
    if (!cstring(type, total) || total - at < 4) return {};
    const int32_t size = int32At(at);
    at += 4;
    const std::string where = "header attribute '" + name + "' (" + type + ") at byte " + std::to_string(at);
    if (size < 0 || uint64_t(size) > total - at)
      return where + " claims " + std::to_string(size) + " bytes, more than the " + std::to_string(total - at) +
             " left in the file";
    const uint64_t end = at + uint64_t(size);
    const uint32_t fixed = fixedAttributeBytes(type);
    if (fixed != 0 && uint32_t(size) != fixed)
      return where + " declares " + std::to_string(size) + " bytes; a " + type + " has " + std::to_string(fixed);
    if (type == "chlist") {  // entries (name, 16 bytes) up to an empty name, which must be the last byte
      for (;;) {
        if (!cstring(channel, end)) return where + " is not a channel list that ends with its attribute";
        if (channel.empty()) break;
        if (end - at < 16) return where + ": channel '" + channel + "' runs past the attribute";
        at += 16;
      }
      if (at != end) return where + " has bytes after its channel list";
    } else if (type == "stringvector") {  // (int32 length, bytes) up to the attribute's end
      while (at < end) {
        if (end - at < 4) return where + " ends inside a string length";
        const int32_t length = int32At(at);
        at += 4;
        if (length < 0 || uint64_t(length) > end - at)
          return where + " holds a string of " + std::to_string(length) + " bytes, more than the attribute's " +
                 std::to_string(end - at) + " left";
        at += uint64_t(length);
      }
    } else if (type == "preview") {  // uint32 width, height, then width x height RGBA bytes
      const uint64_t pixels =
          size >= 8 ? uint64_t(uint32_t(int32At(at))) * uint64_t(uint32_t(int32At(at + 4))) : ~uint64_t(0);
      if (size < 8 || pixels > (uint64_t(size) - 8) / 4 || 8 + 4 * pixels != uint64_t(size))
        return where + ": its preview's width x height does not match its " + std::to_string(size) + " bytes";
    }
    at = end;
  }
}

/// The file as OpenEXR's memory-mapped input stream. Why not OpenEXR's own
/// file stream: OpenEXR allocates each chunk at the size the file claims
/// before reading it (a 1 KB file claiming a 1.6 GB chunk asked for 1.6 GB);
/// from a memory-mapped stream it takes a pointer into the mapping instead,
/// and a claim past the end of the file throws here. Also saves a copy.
class MappedExrStream final : public Imf::IStream {
 public:
  MappedExrStream(const FileView& view, const std::string& path)
      : Imf::IStream(path.c_str()), bytes_(view.data()), size_(view.size()) {}
  bool isMemoryMapped() const override { return true; }
  bool read(char c[], int n) override {
    std::memcpy(c, take(n), size_t(n));
    return position_ < size_;
  }
  char* readMemoryMapped(int n) override { return const_cast<char*>(take(n)); }
  uint64_t tellg() override { return position_; }
  void seekg(uint64_t position) override { position_ = position; }

 private:
  const char* take(int n) {
    if (n < 0 || position_ > size_ || uint64_t(n) > size_ - position_)
      throw std::runtime_error("Early end of file: " + std::to_string(n) + " bytes wanted at byte " +
                               std::to_string(position_) + " of " + std::to_string(size_));
    const char* at = bytes_ + position_;
    position_ += uint64_t(n);
    return at;
  }
  const char* bytes_;
  uint64_t size_;
  uint64_t position_ = 0;
};

/// OpenEXR's ZIP predictor undone in place: b[i] = b[i - 1] + b[i] - 128
/// (mod 256), a running sum. 16 bytes at a time where SSE2 is there (x86-64
/// always): the byte-serial loop was most of reading a ZIP file.
void undoZipPredictor(uint8_t* b, size_t n) {
  if (n < 2) return;
  size_t i = 1;
#ifdef __SSE2__
  const __m128i bias = _mm_set1_epi8(char(-128));
  uint8_t carry = b[0];
  for (; i + 16 <= n; i += 16) {
    __m128i x = _mm_add_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(b + i)), bias);
    x = _mm_add_epi8(x, _mm_slli_si128(x, 1));  // prefix sums within the 16 bytes
    x = _mm_add_epi8(x, _mm_slli_si128(x, 2));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 4));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 8));
    x = _mm_add_epi8(x, _mm_set1_epi8(char(carry)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(b + i), x);
    carry = b[i + 15];
  }
#endif
  for (; i < n; ++i) b[i] = uint8_t(int(b[i - 1]) + int(b[i]) - 128);
}

/// The pixels of a scanline file compressed with ZIP or ZIPS, or not at all
/// (what vox and most renderers write), read chunk by chunk: Imf gives each
/// chunk's bytes (checking the header and the offset table as readPixels
/// does), libdeflate inflates them, and each line is copied whole. Why not
/// readPixels: it inflates with zlib and converts every sample through a
/// function call, 2.7x the CPU time of this for a 1024^2 float depth image
/// (bench/bench_image_read.cpp; docs/bench-fuse.md, "Reading views"). The same bytes
/// as readPixels for every file it accepts; returns false, having written
/// nothing that matters, for any other kind of file (tiled, deep, other
/// compressions, subsampled channels) or any chunk not as its header says,
/// and readPixels then reads the file and words what is wrong.
bool readScanlineChunks(Imf::InputFile& in, const Imath::Box2i& dw, uint64_t fileBytes, const char* const names[4],
                        Image& image) {
  if constexpr (std::endian::native != std::endian::little) return false;  // EXR's samples are little-endian
  const Imf::Header& h = in.header();
  if (h.hasTileDescription() || (h.hasType() && h.type() != Imf::SCANLINEIMAGE)) return false;
  const Imf::Compression compression = h.compression();
  int linesPerChunk = 0;
  if (compression == Imf::NO_COMPRESSION || compression == Imf::ZIPS_COMPRESSION) linesPerChunk = 1;
  else if (compression == Imf::ZIP_COMPRESSION) linesPerChunk = 16;
  else return false;
  // A line holds each channel's samples in turn, channels in name order.
  const size_t width = image.width;
  size_t lineBytes = 0;
  size_t offsetOf[4] = {0, 0, 0, 0};
  for (auto c = h.channels().begin(); c != h.channels().end(); ++c) {
    if (c.channel().xSampling != 1 || c.channel().ySampling != 1) return false;
    for (uint32_t k = 0; k < image.channels; ++k)
      if (std::strcmp(c.name(), names[k]) == 0) offsetOf[k] = lineBytes;
    lineBytes += width * (c.channel().type == Imf::HALF ? 2 : 4);
  }
  // The plausibility rule of readExr, over every channel a line holds.
  if (uint64_t(lineBytes) * image.height > (fileBytes + 1) << 17) return false;
  const size_t sb = sampleBytes(image.type), rowBytes = image.rowBytes();
  const size_t chunkBytes = lineBytes * size_t(linesPerChunk);
  try {
    std::vector<uint8_t> inflated(chunkBytes), lines(chunkBytes);
    std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> inflater(
        libdeflate_alloc_decompressor(), libdeflate_free_decompressor);
    if (!inflater) return false;
    for (int64_t y = dw.min.y; y <= dw.max.y; y += linesPerChunk) {
      const size_t n = size_t(std::min<int64_t>(linesPerChunk, int64_t(dw.max.y) - y + 1));
      const size_t expected = n * lineBytes;
      const char* packed = nullptr;
      int packedBytes = 0;
      in.rawPixelData(int(y), packed, packedBytes);
      const uint8_t* data = reinterpret_cast<const uint8_t*>(packed);
      if (packedBytes < 0) return false;
      if (size_t(packedBytes) != expected) {  // stored as is when compressing did not make it smaller
        if (compression == Imf::NO_COMPRESSION) return false;
        size_t produced = 0;
        if (libdeflate_zlib_decompress(inflater.get(), packed, size_t(packedBytes), inflated.data(), expected,
                                       &produced) != LIBDEFLATE_SUCCESS ||
            produced != expected)
          return false;
        // OpenEXR's ZIP predictor, then its split of even and odd bytes.
        undoZipPredictor(inflated.data(), expected);
        const uint8_t* evens = inflated.data();
        const uint8_t* odds = inflated.data() + (expected + 1) / 2;
        for (size_t i = 0; i < expected / 2; ++i) lines[2 * i] = evens[i], lines[2 * i + 1] = odds[i];
        if (expected % 2) lines[expected - 1] = evens[expected / 2];
        data = lines.data();
      }
      for (size_t l = 0; l < n; ++l) {
        const uint8_t* line = data + l * lineBytes;
        uint8_t* row = image.pixels.data() + (size_t(y - dw.min.y) + l) * rowBytes;
        if (image.channels == 1) {
          std::memcpy(row, line + offsetOf[0], rowBytes);
          continue;
        }
        for (uint32_t k = 0; k < image.channels; ++k)
          for (size_t x = 0; x < width; ++x)
            std::memcpy(row + (x * image.channels + k) * sb, line + offsetOf[k] + x * sb, sb);
      }
    }
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

Image readExr(const std::string& path) {
  requireRegularFile(path);
  if (!isExrFile(path)) throwBadInput(path + ": not an OpenEXR file (wrong magic number or unreadable)");
  const FileView view(path);
  if (const std::string why = headerProblem(view.data(), view.size()); !why.empty())
    throwBadInput(path + ": corrupt or truncated EXR: " + why);
  Image image;
  try {
    MappedExrStream stream(view, path);
    Imf::InputFile in(stream);
    const Imf::Header& h = in.header();
    const Imath::Box2i dw = h.dataWindow();
    image.width = uint32_t(dw.max.x - dw.min.x + 1);
    image.height = uint32_t(dw.max.y - dw.min.y + 1);
    image.channels = 0;
    Imf::PixelType type = Imf::HALF;
    // R, G, B, A as far as they go; a file with one channel is read whatever
    // its name (depth renderers write Z, gray images Y).
    std::vector<std::string> all;
    for (auto c = h.channels().begin(); c != h.channels().end(); ++c) all.emplace_back(c.name());
    const char* names[4] = {kChannelNames[0], kChannelNames[1], kChannelNames[2], kChannelNames[3]};
    if (all.size() == 1) names[0] = all[0].c_str();
    for (uint32_t ch = 0; ch < 4; ++ch) {
      const Imf::Channel* c = h.channels().findChannel(names[ch]);
      if (!c) break;
      if (ch == 0) type = c->type;
      else if (c->type != type) throwBadInput(path + ": channels of different types are not supported");
      ++image.channels;
    }
    if (image.channels == 0)
      throwBadInput(path + ": no R channel (channels " + joinNames(all) + "); vox reads R, G, B, A or a file's only channel");
    for (const std::string& name : all)
      if (std::find(names, names + image.channels, name) == names + image.channels) image.channelsNotRead.push_back(name);
    image.type = type == Imf::UINT ? SampleType::U32 : type == Imf::HALF ? SampleType::F16 : SampleType::F32;
    // A data window its file could not hold compressed is refused before its
    // pixels are allocated: a 1 KB render edited to claim 16777216 x 6 pixels
    // was read as an image (0.43 GB, 2.6 s). No EXR compression expands more
    // than 2^17:1 (deflate 1032:1, RLE 64:1, PIZ's run codes about 300:1,
    // DWA's run-length then deflate stages below 2^17 together).
    const uint64_t decoded = uint64_t(image.rowBytes()) * image.height;
    const uint64_t fileBytes = view.size();
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
      fb.insert(names[ch], Imf::Slice(type, base + ch * sb, image.channels * sb, image.rowBytes()));
    if (!readScanlineChunks(in, dw, fileBytes, names, image)) {
      in.setFrameBuffer(fb);
      in.readPixels(dw.min.y, dw.max.y);
    }
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
