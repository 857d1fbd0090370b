// The views file of `vox fuse` (docs/fuse.md "The views file"): cameras, depth
// images, label images and label-to-class maps, read and checked with errors
// naming the views file, the view and the image.
//
//   {"grid": {"dims": [X, Y, Z], "voxel_size": s, "origin": [x, y, z]},   optional
//    "classes": [class table],                                           optional
//    "labels": LABELS, "depth_kind": "distance" | "z",                    defaults for every view
//    "depth_scale": s, "depth_offset": o, "far": f,
//    "views": [{"depth": "d.exr", "label": "l.png",
//               "camera": CAMERA,                                          optional
//               "normal": "n.png",                                         optional
//               "color": "c.png",                                          optional
//               "confidence": "w.png",                                     optional
//               "labels": ..., "depth_kind": ..., "depth_scale": ..., "depth_offset": ..., "far": ...}]}
//
// CAMERA: {"viewMatrix": [16], "projectionMatrix": [16]} (column-major, the
// block-map format's metadata.json view), {"eye", "target", "up", "fov"}
// (a look-at camera, fov vertical in degrees), or {"intrinsics": {"fx", "fy",
// "cx", "cy"}, "pose": [16]} (pixels, OpenCV: x right, y down, z forward,
// pixel (x, y)'s centre at (x, y); pose = camera-to-world, column-major).
// Without "camera", the depth image's `vox:canonical` entry gives it (the
// images render-canonical writes).
// LABELS: "class-colors" (an RGB(A) 8-bit image whose colours are the class
// table's display colours; alpha 0 = no class), or an object mapping a label
// ("7" for a gray value, "#rrggbb" for a colour) to a class id, a class name,
// or null (no class: the pixel is skipped). Without a map, a gray label is the
// class id itself (0 = no class) and a colour label means "class-colors".
// "normal": a render-canonical normal image (RGBA8, components -1/0/+1 as
// 0/128/255, alpha 0 = miss): the axis of the face each ray entered, used only
// to tell apart crossings whose distances round to the same float (fuse.h).
// "color": an 8-bit RGB(A) PNG (sRGB, alpha 0 = no colour): each voting
// pixel adds its colour to the voxel (averaged in linear light).
// "confidence": a gray 8/16-bit PNG: each pixel's value multiplies its
// votes (--weight); 0 skips the pixel.
// Paths are relative to the views file's folder.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "libvox/core/classes.h"
#include "libvox/core/scene_header.h"
#include "libvox/render/fuse.h"

namespace vox {

struct FuseGridSpec {
  Dims dims;
  double voxelSize = 1;
  std::array<double, 3> origin{0, 0, 0};
};

struct FuseViewSpec {
  int index = 0;
  std::string where;  // "VIEWS.json: views[3]"
  std::string depthPath, labelPath, normalPath, colorPath, confidencePath;  // the last three may be empty
  std::optional<nlohmann::json> camera;
  nlohmann::json labels;  // null when not given
  std::optional<DepthKind> depthKind;
  double depthScale = 1, depthOffset = 0, far = 0;
};

struct FuseViewsFile {
  std::string path;
  std::optional<FuseGridSpec> grid;
  std::optional<ClassTable> classes;
  std::vector<FuseViewSpec> views;
  /// Keys the file gives that no view or file setting reads (a misspelt
  /// "colour" would otherwise drop the colours without a word), one line per
  /// key, naming the first view that gives it and how many more do.
  std::vector<std::string> warnings;
};

/// Reads and checks the views file (not the images). Throws vox::Error
/// (BadInput) naming the file and the element.
FuseViewsFile readFuseViews(const std::string& path);

/// One view with its images loaded and checked.
struct LoadedFuseView {
  FuseView view;
  std::optional<FuseGridSpec> imageGrid;  // the depth image's `vox:canonical` placement, if it has one
  std::vector<std::string> files;         // the images read (for depfiles)
};

/// Loads `spec`'s depth and label images, makes its camera and maps its
/// labels to classes of `classes`. `kindOverride` (the command line's
/// --depth-kind) wins over the file's. Throws vox::Error (BadInput) naming the
/// view and the image: a missing or unreadable image, a depth image that is
/// not one float channel (EXR) or one 16-bit channel (PNG), a label image of
/// another size than the depth image, a label not in the map, a map naming a
/// class not in the table, a camera whose matrices are singular.
LoadedFuseView loadFuseView(const FuseViewSpec& spec, const ClassTable& classes, std::optional<DepthKind> kindOverride);

}  // namespace vox
