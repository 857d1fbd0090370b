#include "formats/vdb/vdb_checked_file.h"

#include <filesystem>
#include <fstream>
#include <new>

#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {

/// OpenVDB's text of an exception from a corrupt file may quote garbage: short and printable.
std::string printable(const std::exception& e) {
  std::string why;
  for (char c : std::string(e.what()).substr(0, 160)) why += (c >= 32 && c < 127) ? c : '?';
  return why;
}

/// Runs `fn`, turning OpenVDB's exceptions into vox::Error naming the file.
template <typename Fn>
auto guarded(const std::string& path, const std::string& what, Fn&& fn) -> decltype(fn()) {
  try {
    return fn();
  } catch (...) {
    rethrowVdbReadError(path, what);
  }
}

}  // namespace

void rethrowVdbReadError(const std::string& path, const std::string& what) {
  try {
    throw;
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throwIo(path + ": out of memory while reading " + what);
  } catch (const std::exception& e) {
    throwBadInput(path + ": cannot read " + what + " (corrupt?): " + printable(e));
  }
}

CheckedVdbFile::CheckedVdbFile(const std::string& path, VdbCheck depth) : path_(path) {
  checkVdbFileOpenable(path);
  frame_ = checkVdbStructure(path, depth);
  ensureOpenVdbInitialized();
  guarded(path_, "the OpenVDB file", [&] {
    file_ = std::make_unique<openvdb::io::File>(path_);
    file_->open(/*delayLoad=*/false);
  });
}

CheckedVdbFile::~CheckedVdbFile() {
  if (!file_) return;
  try {
    file_->close();
  } catch (...) {
  }
}

const VdbGridFrame* CheckedVdbFile::findGrid(const std::string& uniqueName) const {
  for (const VdbGridFrame& g : frame_.grids)
    if (g.uniqueName == uniqueName) return &g;
  return nullptr;
}

openvdb::MetaMap::Ptr CheckedVdbFile::metadata() const {
  return guarded(path_, "the OpenVDB file metadata", [&] {
    openvdb::MetaMap::Ptr meta = file_->getMetadata();
    return meta ? meta : openvdb::MetaMap::Ptr(new openvdb::MetaMap);
  });
}

openvdb::GridBase::Ptr CheckedVdbFile::readGrid(const std::string& uniqueName) {
  const VdbGridFrame* g = findGrid(uniqueName);
  if (!g) throwBadInput(path_ + ": no grid named '" + uniqueName + "'");
  if (!g->checked)
    throwBadInput(path_ + ": grid '" + uniqueName + "': " +
                  (g->uncheckedWhy.empty() ? std::string("not checked (internal: opened for metadata only)") : g->uncheckedWhy));
  return guarded(path_, "grid '" + uniqueName + "'", [&] { return file_->readGrid(uniqueName); });
}

openvdb::GridPtrVec CheckedVdbFile::readCheckedGrids() {
  openvdb::GridPtrVec out;
  for (const VdbGridFrame& g : frame_.grids)
    if (g.checked) out.push_back(readGrid(g.uniqueName));
  return out;
}

}  // namespace vox
