// vox::Error — the single exception type libvox and formats/ throw.
//
// The library never prints and never exits: it throws an Error whose message names
// the file, the element and what to do, and whose kind tells the CLI which
// documented exit code to use (tools/cli/cli.h maps kinds to codes).
//
// The library does not know the command line: where the fix is to change a
// setting, the message says so in the library's terms ("lower the resolution")
// and `setting` names the setting; the CLI appends the option that sets it
// (tools/cli/dispatch.cpp: "lower the resolution (--res)").
#pragma once

#include <stdexcept>
#include <string>

namespace vox {

enum class ErrorKind {
  Usage,     // the options make no sense together (exit 2)
  BadInput,  // an input file is missing, malformed or not what was expected (exit 3)
  Io,        // the system failed: cannot write an output, disk full (exit 4)
  Resource,  // the run would need more memory than the limit allows (exit 4; libvox/core/memory_budget.h)
  Internal,  // a bug: an invariant did not hold (exit 4)
};

/// A setting an error's fix changes. Named by what it is; the CLI knows its option.
enum class Setting {
  None,
  Resolution,              // voxels on the longest side
  VoxelSize,               // world units per voxel
  VoxelSpacing,            // how fine the grid is: the resolution or the voxel size
  Bounds,                  // the world box that is voxelized
  Padding,                 // empty voxels around the bounds
  FillMode,                // surface or solid
  DropInvalid,             // drop triangles with non-finite vertices, faces of < 3 vertices, instead of refusing
  IgnoreMissingMaterials,  // keep going without a missing material or texture file
  ClassRules,              // the class rules file
  GridThreshold,           // fog volumes: the density that counts as inside
  GridName,                // which grid of an OpenVDB file
  BlockWorldGrid,          // the block world's grid size
  MipLevels,               // how many pyramid levels
  ChunkSide,               // page files: voxels per chunk side
  PageAlignment,           // page files: payload alignment
  PageLayout,              // page files: bricks, svo or columns
  AtlasFormat,             // texel format of an atlas
  AtlasMaxSide,            // largest atlas side
  AtlasTilesPerRow,        // tiles per atlas row
  CameraPose,              // eye, target and up
  CameraUp,                // the up vector
  FieldOfView,             // vertical field of view
  ImageSize,               // image width and height
  RenderLevel,             // which level of a page file is rendered
  MemoryLimit,             // the memory a run may plan to use
};

struct Error : std::runtime_error {
  ErrorKind kind;
  Setting setting = Setting::None;  // the setting the fix changes, if any
  Error(ErrorKind k, const std::string& message, Setting s = Setting::None)
      : std::runtime_error(message), kind(k), setting(s) {}
};

[[noreturn]] inline void throwBadInput(const std::string& message, Setting s = Setting::None) {
  throw Error(ErrorKind::BadInput, message, s);
}
[[noreturn]] inline void throwUsage(const std::string& message, Setting s = Setting::None) {
  throw Error(ErrorKind::Usage, message, s);
}
[[noreturn]] inline void throwIo(const std::string& message) { throw Error(ErrorKind::Io, message); }

}  // namespace vox
