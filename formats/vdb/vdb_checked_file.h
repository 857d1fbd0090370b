// CheckedVdbFile: the way voxbake opens a .vdb file for OpenVDB to read (the
// one-pass scene reader, vdb_scene_direct_read.h, builds voxbake's own scene
// files from the same walk without OpenVDB's reader, and falls back to this).
//
// OpenVDB's reader trusts every size and count in the file (vdb_structure.h
// says what goes wrong). This class refuses anything but a regular file,
// walks the whole file with checkVdbStructure (VdbCheck::Full) before OpenVDB
// sees a byte of it, then opens it with openvdb::io::File, and turns whatever
// OpenVDB still throws into vox::Error (BadInput) naming the file. Grids the
// walk could not check (types other than bool, mask, float, double, int32,
// int64, vec3i, vec3s, vec3d) are never handed to OpenVDB.
//
// The file is read twice (walk, then OpenVDB); a file replaced between the two
// by another process is not protected against.
#pragma once

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <memory>
#include <string>

#include "formats/vdb/vdb_structure.h"

namespace vox {


/// Inside a catch block: rethrows the exception in flight as vox::Error naming
/// `path` (BadInput "PATH: cannot read WHAT (corrupt?): ..." for OpenVDB's
/// exceptions, Io for std::bad_alloc); a vox::Error is rethrown unchanged.
[[noreturn]] void rethrowVdbReadError(const std::string& path, const std::string& what);

class CheckedVdbFile {
 public:
  /// Checks and opens `path`. Throws vox::Error (BadInput) when it is missing,
  /// unreadable, not a regular file, not an OpenVDB file, or corrupt. With
  /// VdbCheck::Framing only the header, file metadata and grid descriptors are
  /// walked: enough for metadata(), and readGrid() refuses every grid.
  explicit CheckedVdbFile(const std::string& path, VdbCheck depth = VdbCheck::Full);
  ~CheckedVdbFile();
  CheckedVdbFile(const CheckedVdbFile&) = delete;
  CheckedVdbFile& operator=(const CheckedVdbFile&) = delete;

  const std::string& path() const { return path_; }
  const VdbFrame& frame() const { return frame_; }
  /// The grid of that unique name, or nullptr.
  const VdbGridFrame* findGrid(const std::string& uniqueName) const;

  /// The file-level metadata.
  openvdb::MetaMap::Ptr metadata() const;
  /// Reads one grid (its instance parent's tree for an instance). Throws
  /// vox::Error (BadInput) when there is no such grid, its type could not be
  /// checked, or OpenVDB fails.
  openvdb::GridBase::Ptr readGrid(const std::string& uniqueName);
  /// Reads every grid whose payload was checked, in file order; grids that
  /// could not be checked are skipped (frame() lists them).
  openvdb::GridPtrVec readCheckedGrids();

 private:
  std::string path_;
  VdbFrame frame_;
  std::unique_ptr<openvdb::io::File> file_;
};

}  // namespace vox
