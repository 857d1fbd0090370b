#include "formats/vdb/vdb_structure.h"

#include <cstring>

#include "formats/core/file_util.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

// OpenVDB file format versions that change the framing (openvdb/version.h).
constexpr uint32_t kVersionLibraryVersion = 211, kVersionGridOffsets = 212, kVersionGridInstancing = 216,
                   kVersionBoostUuid = 217, kVersionSelectiveCompression = 220, kVersionNodeMaskCompression = 222;
constexpr int64_t kMagic = 0x56444220;

class Reader {
 public:
  Reader(const uint8_t* d, size_t n, const std::string& name) : d_(d), n_(n), name_(name) {}
  size_t pos() const { return pos_; }
  size_t size() const { return n_; }
  void need(size_t bytes, const std::string& what) {
    if (bytes > n_ - pos_)
      throwBadInput(name_ + ": truncated OpenVDB file: " + what + " needs " + std::to_string(bytes) +
                    " bytes at offset " + std::to_string(pos_) + " but the file ends at " + std::to_string(n_));
  }
  template <typename T>
  T get(const std::string& what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, d_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string str(const std::string& what) {
    const uint32_t len = get<uint32_t>(what + " length");
    need(len, what);
    std::string s(reinterpret_cast<const char*>(d_ + pos_), len);
    pos_ += len;
    return s;
  }
  void skip(size_t bytes, const std::string& what) {
    need(bytes, what);
    pos_ += bytes;
  }
  void seek(size_t to) { pos_ = to; }

 private:
  const uint8_t* d_;
  size_t n_, pos_ = 0;
  std::string name_;
};

std::string printable(const std::string& s) {
  std::string out;
  for (char c : s.substr(0, 64)) out += (c >= 32 && c < 127) ? c : '?';
  return out;
}

}  // namespace

VdbFrame checkVdbStructure(const uint8_t* data, size_t size, const std::string& name) {
  Reader r(data, size, name);
  VdbFrame f;
  if (r.get<int64_t>("the magic number") != kMagic) throwBadInput(name + ": not an OpenVDB file (wrong magic number)");
  f.fileVersion = r.get<uint32_t>("the file version");
  if (f.fileVersion < 200 || f.fileVersion > 1000)
    throwBadInput(name + ": OpenVDB file version " + std::to_string(f.fileVersion) + " is not plausible; the file is corrupt");
  if (f.fileVersion >= kVersionLibraryVersion) {
    f.libraryMajor = r.get<uint32_t>("the library major version");
    f.libraryMinor = r.get<uint32_t>("the library minor version");
  }
  bool hasGridOffsets = false;
  if (f.fileVersion >= kVersionGridOffsets) hasGridOffsets = r.get<char>("the grid-offsets flag") != 0;
  if (f.fileVersion >= kVersionSelectiveCompression && f.fileVersion < kVersionNodeMaskCompression)
    r.skip(1, "the compression flag");
  r.skip(f.fileVersion >= kVersionBoostUuid ? 36 : 16, "the file UUID");

  const uint32_t metaCount = r.get<uint32_t>("the file metadata count");
  for (uint32_t i = 0; i < metaCount; ++i) {
    const std::string what = "file metadata entry " + std::to_string(i);
    const std::string key = r.str(what + " name");
    r.str(what + " ('" + printable(key) + "') type");
    const uint32_t bytes = r.get<uint32_t>(what + " ('" + printable(key) + "') size");
    r.skip(bytes, what + " ('" + printable(key) + "') value");
    f.metadataNames.push_back(key);
  }
  if (!hasGridOffsets) return f;  // very old files: nothing more to frame; OpenVDB reads the rest

  const uint32_t gridCount = r.get<uint32_t>("the grid count");
  for (uint32_t i = 0; i < gridCount; ++i) {
    const std::string what = "grid descriptor " + std::to_string(i);
    VdbGridFrame g;
    g.uniqueName = r.str(what + " name");
    g.type = r.str(what + " ('" + printable(g.uniqueName) + "') type");
    if (f.fileVersion >= kVersionGridInstancing) r.str(what + " instance parent");
    g.gridPos = r.get<int64_t>(what + " grid offset");
    g.blockPos = r.get<int64_t>(what + " block offset");
    g.endPos = r.get<int64_t>(what + " end offset");
    const std::string who = "grid '" + printable(g.uniqueName) + "'";
    if (g.gridPos != int64_t(r.pos()) || g.blockPos < g.gridPos || g.endPos < g.blockPos)
      throwBadInput(name + ": " + who + " has inconsistent offsets (grid " + std::to_string(g.gridPos) + ", blocks " +
                    std::to_string(g.blockPos) + ", end " + std::to_string(g.endPos) + "); the file is corrupt");
    if (g.endPos > int64_t(r.size()))
      throwBadInput(name + ": truncated OpenVDB file: " + who + " ends at byte " + std::to_string(g.endPos) +
                    " but the file has " + std::to_string(r.size()) + " bytes");
    r.seek(size_t(g.endPos));
    f.grids.push_back(std::move(g));
  }
  return f;
}

VdbFrame checkVdbStructure(const std::string& path) {
  const FileView file(path);  // mapped: the walk touches only the framing
  return checkVdbStructure(reinterpret_cast<const uint8_t*>(file.data()), file.size(), path);
}

}  // namespace vox
