#include "formats/image/fuse_views.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unordered_map>

#include "formats/core/file_util.h"
#include "formats/core/json_fields.h"
#include "formats/core/json_input.h"
#include "formats/image/image.h"
#include "formats/image/render_meta.h"
#include "formats/scene/class_table_json.h"
#include "libvox/core/error.h"
#include "libvox/render/intrinsics.h"

namespace vox {

using json = nlohmann::json;

namespace {

[[noreturn]] void bad(const std::string& where, const std::string& what) { throwBadInput(where + ": " + what); }

std::optional<DepthKind> depthKindOf(const json& j, const std::string& where) {
  const std::string s = jsonString(j, where, "depth_kind");
  if (s == "distance") return DepthKind::Distance;
  if (s == "z") return DepthKind::Z;
  bad(where, "depth_kind must be \"distance\" (the distance from the eye along the ray) or \"z\" (camera-space depth)");
}

std::string resolve(const std::string& base, const std::string& p) {
  if (p.empty() || std::filesystem::path(p).is_absolute()) return p;
  const std::filesystem::path dir = std::filesystem::path(base).parent_path();
  return dir.empty() ? p : (dir / p).string();
}

std::array<double, 3> triple(const json& j, const std::string& where, const std::string& element) {
  if (!j.is_array() || j.size() != 3) bad(where, element + " must be [x, y, z]");
  std::array<double, 3> out;
  for (size_t i = 0; i < 3; ++i) {
    out[i] = jsonNumber(j[i], where, element + "[" + std::to_string(i) + "]");
    if (!std::isfinite(out[i])) bad(where, element + "[" + std::to_string(i) + "] must be finite");
  }
  return out;
}

Mat4d matrix(const json& j, const std::string& where, const std::string& element) {
  if (!j.is_array() || j.size() != 16) bad(where, element + " must be an array of 16 numbers (column-major)");
  Mat4d m;
  for (size_t i = 0; i < 16; ++i) m[i] = jsonNumber(j[i], where, element + "[" + std::to_string(i) + "]");
  return m;
}

// The three per-view settings that may also be file-wide defaults.
void readDepthSettings(const json& j, const std::string& where, FuseViewSpec& s) {
  if (j.contains("depth_kind")) s.depthKind = depthKindOf(j["depth_kind"], where);
  if (j.contains("depth_scale")) {
    s.depthScale = jsonNumber(j["depth_scale"], where, "depth_scale");
    if (!(std::isfinite(s.depthScale) && s.depthScale > 0)) bad(where, "depth_scale must be a finite number > 0");
  }
  if (j.contains("depth_offset")) {
    s.depthOffset = jsonNumber(j["depth_offset"], where, "depth_offset");
    if (!std::isfinite(s.depthOffset)) bad(where, "depth_offset must be finite");
  }
  if (j.contains("far")) {
    s.far = jsonNumber(j["far"], where, "far");
    if (!(s.far > 0)) bad(where, "far must be a number > 0 (depths beyond it are skipped)");
  }
  if (j.contains("labels")) {
    const json& l = j["labels"];
    if (!(l.is_object() || (l.is_string() && l.get<std::string>() == "class-colors")))
      bad(where, "labels must be \"class-colors\" or an object mapping a label (\"7\" or \"#rrggbb\") to a class id, "
                 "a class name or null");
    s.labels = l;
  }
}

Camera cameraOf(const json& c, uint32_t W, uint32_t H, const std::string& where) {
  if (!c.is_object()) bad(where, "camera must be an object (viewMatrix + projectionMatrix, eye + target, or intrinsics + pose)");
  if (c.contains("viewMatrix") || c.contains("projectionMatrix")) {
    const Mat4d view = matrix(jsonMember(c, "viewMatrix", where + ".camera"), where, "camera.viewMatrix");
    const Mat4d proj = matrix(jsonMember(c, "projectionMatrix", where + ".camera"), where, "camera.projectionMatrix");
    return Camera::make(view, proj, W, H, where + ".camera");
  }
  if (c.contains("eye")) {
    // "size" and "view" as render-canonical --camera-out writes them (the
    // size is always the depth image's); anything else is a misspelling.
    jsonOnlyKeys(c, {"eye", "target", "up", "fov", "size", "view"}, where, "camera");
    const Vec3d eye = triple(c["eye"], where, "camera.eye");
    const Vec3d target = triple(jsonMember(c, "target", where + ".camera"), where, "camera.target");
    const Vec3d up = c.contains("up") ? triple(c["up"], where, "camera.up") : kLookAtUp;
    const double fov = c.contains("fov") ? jsonNumber(c["fov"], where, "camera.fov") : kLookAtFovYDegrees;
    if (!(fov > 0 && fov < 180)) bad(where, "camera.fov must be in (0, 180) degrees");
    try {
      return Camera::lookAt(eye, target, up, fov, W, H);
    } catch (const Error& e) {
      bad(where, "camera: " + withoutCameraLead(e.what()));
    }
  }
  if (c.contains("intrinsics")) {
    const json& k = c["intrinsics"];
    if (!k.is_object()) bad(where, "camera.intrinsics must be {\"fx\", \"fy\", \"cx\", \"cy\"} in pixels");
    jsonOnlyKeys(c, {"intrinsics", "pose"}, where, "camera");
    jsonOnlyKeys(k, {"fx", "fy", "cx", "cy"}, where, "camera.intrinsics");
    const std::string kw = where + ".camera.intrinsics";
    Intrinsics in;
    in.fx = jsonNumber(jsonMember(k, "fx", kw), where, "camera.intrinsics.fx");
    in.fy = jsonNumber(jsonMember(k, "fy", kw), where, "camera.intrinsics.fy");
    in.cx = jsonNumber(jsonMember(k, "cx", kw), where, "camera.intrinsics.cx");
    in.cy = jsonNumber(jsonMember(k, "cy", kw), where, "camera.intrinsics.cy");
    const Mat4d pose = matrix(jsonMember(c, "pose", where + ".camera"), where, "camera.pose");
    return intrinsicsCamera(in, pose, W, H, where + ".camera");
  }
  bad(where, "camera needs viewMatrix + projectionMatrix, eye + target, or intrinsics + pose");
}

Image readImage(const std::string& path, const std::string& where, const std::string& role) {
  try {
    requireRegularFile(path);  // "no such file", or what else it is (a directory...)
  } catch (const Error& e) {
    bad(where, role + " image " + e.what());
  }
  try {
    if (isExrFile(path)) return readExr(path);
    if (isPngFile(path)) return readPng(path);
  } catch (const Error& e) {
    bad(where, role + " image: " + e.what());
  }
  bad(where, role + " image " + path + " is neither PNG nor EXR");
}

std::string hexColor(uint32_t c) {
  char s[8];
  std::snprintf(s, sizeof s, "#%06x", c & 0xFFFFFFu);
  return s;
}

/// FuseViewsFile::warnings: the keys of the file and of its views that
/// nothing reads.
void noteUnreadKeys(const json& doc, const json& views, FuseViewsFile& out) {
  static const std::vector<std::string> kSettings = {"depth_kind", "depth_scale", "depth_offset", "far", "labels"};
  auto with = [](std::vector<std::string> own) {
    own.insert(own.end(), kSettings.begin(), kSettings.end());
    return own;
  };
  static const std::vector<std::string> kFile = with({"grid", "classes", "views"});
  static const std::vector<std::string> kView = with({"depth", "label", "camera", "normal", "color", "confidence"});
  for (const std::string& key : jsonUnknownKeys(doc, kFile))
    out.warnings.push_back(out.path + ": \"" + key + "\" is not a key of a views file (" + jsonKeyList(kFile) +
                           "); it is ignored");
  // Per key: the first view that gives it, and how many do.
  std::vector<std::pair<std::string, std::pair<size_t, size_t>>> unread;
  for (size_t i = 0; i < views.size(); ++i)
    for (const std::string& key : jsonUnknownKeys(views[i], kView)) {
      auto at = std::find_if(unread.begin(), unread.end(), [&](const auto& u) { return u.first == key; });
      if (at == unread.end()) unread.push_back({key, {i, 1}});
      else ++at->second.second;
    }
  for (const auto& [key, seen] : unread) {
    const size_t more = seen.second - 1;
    const std::string others = more == 0 ? "" : " and " + std::to_string(more) + (more > 1 ? " more views" : " more view");
    out.warnings.push_back(out.path + ": views[" + std::to_string(seen.first) + "]" + others + ": \"" + key +
                           "\" is not a key of a view (" + jsonKeyList(kView) + "); it is ignored");
  }
}

}  // namespace

FuseViewsFile readFuseViews(const std::string& path) {
  FuseViewsFile out;
  out.path = path;
  requireRegularFile(path);
  json doc;
  try {
    doc = parseJsonInput(readFileBytes(path), path);
  } catch (const json::exception& e) {
    bad(path, std::string("not valid JSON: ") + e.what());
  }
  if (!doc.is_object()) bad(path, "the views file is a JSON object with \"views\": [...]");
  if (doc.contains("grid")) {
    const json& g = doc["grid"];
    const std::string w = path + ": grid";
    if (!g.is_object()) bad(path, "grid must be {\"dims\": [X, Y, Z], \"voxel_size\": s, \"origin\": [x, y, z]}");
    FuseGridSpec spec;
    spec.dims = jsonDims(jsonMember(g, "dims", w), path, "grid.dims");
    spec.voxelSize = jsonNumber(jsonMember(g, "voxel_size", w), path, "grid.voxel_size");
    spec.origin = triple(jsonMember(g, "origin", w), path, "grid.origin");
    const std::string problem = placementProblem(spec.voxelSize, spec.origin, spec.dims);
    if (!problem.empty()) bad(path, "grid: " + problem);
    out.grid = spec;
  }
  if (doc.contains("classes")) out.classes = classTableFromJson(doc["classes"], ClassJsonForm::HandWritten, path + ": classes");
  FuseViewSpec defaults;
  readDepthSettings(doc, path, defaults);
  const json& views = jsonMember(doc, "views", path);
  if (!views.is_array() || views.empty()) bad(path, "views must be a non-empty array of views");
  for (size_t i = 0; i < views.size(); ++i) {
    const json& v = views[i];
    FuseViewSpec s = defaults;
    s.index = int(i);
    s.where = path + ": views[" + std::to_string(i) + "]";
    if (!v.is_object()) bad(s.where, "must be an object with \"depth\" and \"label\"");
    s.depthPath = resolve(path, jsonString(jsonMember(v, "depth", s.where), s.where, "depth"));
    s.labelPath = resolve(path, jsonString(jsonMember(v, "label", s.where), s.where, "label"));
    if (v.contains("camera")) s.camera = v["camera"];
    if (v.contains("normal")) s.normalPath = resolve(path, jsonString(v["normal"], s.where, "normal"));
    if (v.contains("color")) s.colorPath = resolve(path, jsonString(v["color"], s.where, "color"));
    if (v.contains("confidence")) s.confidencePath = resolve(path, jsonString(v["confidence"], s.where, "confidence"));
    readDepthSettings(v, s.where, s);
    out.views.push_back(std::move(s));
  }
  noteUnreadKeys(doc, views, out);
  return out;
}

LoadedFuseView loadFuseView(const FuseViewSpec& spec, const ClassTable& classes, std::optional<DepthKind> kindOverride) {
  LoadedFuseView out;
  const std::string& where = spec.where;
  const Image depth = readImage(spec.depthPath, where, "depth");
  out.files.push_back(spec.depthPath);
  const std::string depthName = "depth " + spec.depthPath;
  FuseView& view = out.view;
  const size_t N = size_t(depth.width) * depth.height;
  view.depth.resize(N);
  const bool exr = isExrFile(spec.depthPath);
  if (exr) {
    if (depth.channels != 1 || !depth.channelsNotRead.empty() ||
        !(depth.type == SampleType::F32 || depth.type == SampleType::F16)) {
      const size_t n = depth.channels + depth.channelsNotRead.size();
      std::string has = n == 1 ? "one channel" : std::to_string(n) + " channels (";
      if (n > 1) {
        static const char* const kRgba[4] = {"R", "G", "B", "A"};
        for (uint32_t c = 0; c < depth.channels && c < 4; ++c) has += std::string(c ? ", " : "") + kRgba[c];
        for (const std::string& c : depth.channelsNotRead) has += ", " + c;
        has += ")";
      }
      bad(where, depthName + ": a depth EXR has one float channel (any name: R, Z, Y...); this one has " + has +
                     " of " + sampleTypeName(depth.type) +
                     "; keep the depth alone, e.g. oiiotool IN.exr --ch Z -o depth.exr");
    }
    if (depth.type == SampleType::F32) {
      for (uint32_t y = 0; y < depth.height; ++y) {
        const float* row = depth.row<float>(y);
        for (uint32_t x = 0; x < depth.width; ++x) view.depth[size_t(y) * depth.width + x] = double(row[x]) * spec.depthScale + spec.depthOffset;
      }
      view.measure.float32 = spec.depthScale == 1 && spec.depthOffset == 0;
    } else {
      bad(where, depthName + ": half-float depth loses too much; write the depth as 32-bit float");
    }
  } else {
    if (depth.channels != 1 || depth.type != SampleType::U16)
      bad(where, depthName + ": a depth PNG has one 16-bit channel (depth = value * depth_scale + depth_offset, 0 = "
                             "no depth); this one has " + std::to_string(depth.channels) + " channel(s) of " +
                             sampleTypeName(depth.type));
    for (uint32_t y = 0; y < depth.height; ++y) {
      const uint16_t* row = depth.row<uint16_t>(y);
      for (uint32_t x = 0; x < depth.width; ++x)
        view.depth[size_t(y) * depth.width + x] =
            row[x] == 0 ? 0.0 : double(row[x]) * spec.depthScale + spec.depthOffset;
    }
    view.measure.float32 = false;
  }
  view.measure.kind = kindOverride ? *kindOverride : spec.depthKind.value_or(DepthKind::Distance);
  view.far = spec.far;

  // The camera: the views file's, or the depth image's own.
  const std::optional<RenderMeta> meta = readRenderMeta(depth, spec.depthPath);
  if (meta) {
    FuseGridSpec g;
    g.dims = meta->dims;
    g.voxelSize = meta->voxelSize;
    g.origin = meta->origin;
    out.imageGrid = g;
  }
  if (spec.camera) {
    view.camera = cameraOf(*spec.camera, depth.width, depth.height, where);
  } else {
    if (!meta)
      bad(where, "no \"camera\", and " + depthName + " carries no vox:canonical entry to take it from; give the view a "
                 "\"camera\"");
    view.camera = renderCamera(*meta, depth, where + ": " + depthName,
                               "fuse the image as rendered, or give the view a \"camera\" for this image");
  }

  // A view's other images: read, recorded as inputs, and of the depth image's size.
  auto readBeside = [&](const std::string& path, const std::string& role) {
    Image image = readImage(path, where, role);
    out.files.push_back(path);
    if (image.width != depth.width || image.height != depth.height)
      bad(where, role + " " + path + " is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                     " but " + depthName + " is " + std::to_string(depth.width) + "x" + std::to_string(depth.height) +
                     "; a view's images must have one size");
    return image;
  };

  // Labels.
  const Image label = readBeside(spec.labelPath, "label");
  const std::string labelName = "label " + spec.labelPath;
  const bool colour = label.channels >= 3;
  if (!isPngFile(spec.labelPath) || (colour && label.type != SampleType::U8))
    bad(where, labelName + ": a label image is an 8/16-bit gray PNG (the label value) or an 8-bit RGB(A) PNG (a colour "
                           "per label); this one has " + std::to_string(label.channels) + " channel(s) of " +
                           sampleTypeName(label.type));
  // The map: label value -> class id (0 = no class).
  std::unordered_map<uint32_t, uint8_t> map;
  bool identity = false;
  auto classOf = [&](const json& value, const std::string& element) -> uint8_t {
    if (value.is_null()) return 0;
    if (value.is_number_integer()) {
      const int64_t id = value.get<int64_t>();
      if (id < 1 || id > kMaxClassId || !classes.find(uint8_t(id)))
        bad(where, element + ": class id " + std::to_string(id) + " is not in the class table");
      return uint8_t(id);
    }
    if (value.is_string()) {
      const ClassInfo* c = classes.findByName(value.get<std::string>());
      if (!c) bad(where, element + ": no class named '" + value.get<std::string>() + "' in the class table");
      return c->id;
    }
    bad(where, element + " must be a class id, a class name or null");
  };
  if (spec.labels.is_string() || (spec.labels.is_null() && colour)) {
    if (!colour) bad(where, labelName + ": \"class-colors\" needs an RGB(A) label image (a render's class mode)");
    for (const ClassInfo& c : classes.classes()) {
      const uint32_t key = (uint32_t(c.color.r) << 16) | (uint32_t(c.color.g) << 8) | c.color.b;
      if (!map.emplace(key, c.id).second)
        bad(where, "labels \"class-colors\": classes " + std::to_string(map[key]) + " and " + std::to_string(c.id) +
                       " share the display colour " + hexColor(key) + "; give an explicit label map");
    }
  } else if (spec.labels.is_null()) {
    identity = true;
  } else {
    // Keys that spell one label twice ("#57ad5c" and "#57AD5C", "7" and
    // "07"): one mapping would be dropped without a word, as with a key given
    // twice.
    std::unordered_map<uint32_t, std::string> spelt;
    for (const auto& [k, value] : spec.labels.items()) {
      const std::string element = "labels[\"" + k + "\"]";
      uint32_t key = 0;
      if (!k.empty() && k[0] == '#') {
        if (!colour) bad(where, element + ": a colour label, but " + labelName + " is a gray image");
        if (k.size() != 7 || k.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos)
          bad(where, element + ": a colour label is written #rrggbb");
        key = uint32_t(std::stoul(k.substr(1), nullptr, 16));
      } else {
        if (colour) bad(where, element + ": a gray label, but " + labelName + " is an RGB(A) image; write #rrggbb");
        if (k.empty() || k.size() > 5 || k.find_first_not_of("0123456789") != std::string::npos || std::stoul(k) > 65535)
          bad(where, element + ": a gray label is an integer 0..65535");
        key = uint32_t(std::stoul(k));
      }
      const auto [first, isNew] = spelt.emplace(key, k);
      if (!isNew)
        bad(where, element + " and labels[\"" + first->second + "\"] are the same label; keep one of them");
      map[key] = classOf(value, element);
    }
  }
  view.classes.resize(N);
  // Neighbouring pixels mostly carry the same label: the last one found in the
  // map is tried first (the map lookup was a tenth of reading a view).
  uint32_t lastKey = 0;
  uint8_t lastClass = 0;
  bool haveLast = false;
  // An RGBA pixel equal to the one before it (most are) takes its class.
  uint32_t lastPixel = 0;
  bool havePixel = false;
  const bool rgba8 = colour && label.channels == 4;
  const size_t labelRowBytes = label.rowBytes();
  for (uint32_t y = 0; y < label.height; ++y) {
    const uint8_t* labelRow = label.pixels.data() + size_t(y) * labelRowBytes;
    for (uint32_t x = 0; x < label.width; ++x) {
      const size_t i = size_t(y) * label.width + x;
      uint32_t pixel = 0;
      if (rgba8) {
        std::memcpy(&pixel, labelRow + size_t(x) * 4, 4);
        if (havePixel && pixel == lastPixel) {
          view.classes[i] = view.classes[i - 1];
          continue;
        }
      }
      uint32_t key = 0;
      bool none = false;
      if (colour) {
        const uint8_t* p = labelRow + size_t(x) * label.channels;
        key = (uint32_t(p[0]) << 16) | (uint32_t(p[1]) << 8) | p[2];
        none = label.channels == 4 && p[3] == 0;
      } else if (label.type == SampleType::U8) {
        const uint8_t* p = labelRow + size_t(x) * label.channels;
        key = p[0];
        none = label.channels == 2 && p[1] == 0;
      } else {
        const uint16_t* p = reinterpret_cast<const uint16_t*>(labelRow) + size_t(x) * label.channels;
        key = p[0];
        none = label.channels == 2 && p[1] == 0;
      }
      if (rgba8) lastPixel = pixel, havePixel = true;  // set here: pixel i - 1 then has its class when it is reused
      if (none) {
        view.classes[i] = 0;
        continue;
      }
      // A label outside the map where the depth image has nothing (a
      // segmenter's "unknown" often sits where the depth estimator gave no
      // depth) is never voted: fuse skips the pixel and counts it no_depth.
      // Class 0 here; the next pixel of the same colour is looked up afresh.
      auto unmappedWithoutDepth = [&] {
        if (view.hasDepth(i)) return false;
        view.classes[i] = 0;
        havePixel = false;
        return true;
      };
      if (identity) {
        if (key != 0 && (key > uint32_t(kMaxClassId) || !classes.find(uint8_t(key)))) {
          if (unmappedWithoutDepth()) continue;
          bad(where, labelName + ": label " + std::to_string(key) + " at pixel (" + std::to_string(x) + ", " +
                         std::to_string(y) + ") is no class id of the table; give the view a \"labels\" map");
        }
        view.classes[i] = uint8_t(key);
        continue;
      }
      if (haveLast && key == lastKey) {
        view.classes[i] = lastClass;
        continue;
      }
      const auto it = map.find(key);
      if (it == map.end()) {
        if (unmappedWithoutDepth()) continue;
        bad(where, labelName + ": label " + (colour ? hexColor(key) : std::to_string(key)) + " at pixel (" +
                       std::to_string(x) + ", " + std::to_string(y) + ") is not in the label map" +
                       (spec.labels.is_string() || spec.labels.is_null()
                            ? " (no class has that display colour; for a render of a scene with its own classes, "
                              "give the views file that scene's \"classes\", or fuse with -i)"
                            : ""));
      }
      view.classes[i] = it->second;
      lastKey = key;
      lastClass = it->second;
      haveLast = true;
    }
  }

  if (!spec.colorPath.empty()) {
    const Image color = readBeside(spec.colorPath, "color");
    const std::string colorName = "color " + spec.colorPath;
    if (!isPngFile(spec.colorPath) || color.channels < 3 || color.type != SampleType::U8)
      bad(where, colorName + ": a colour image is an 8-bit RGB or RGBA PNG (sRGB); this one has " +
                     std::to_string(color.channels) + " channel(s) of " + sampleTypeName(color.type));
    view.color.assign(N, FuseView::kNoColor);
    for (uint32_t y = 0; y < color.height; ++y)
      for (uint32_t x = 0; x < color.width; ++x) {
        const uint8_t* p = color.row<uint8_t>(y) + size_t(x) * color.channels;
        if (color.channels == 4 && p[3] == 0) continue;
        view.color[size_t(y) * color.width + x] = (uint32_t(p[0]) << 16) | (uint32_t(p[1]) << 8) | p[2];
      }
  }

  if (!spec.confidencePath.empty()) {
    const Image conf = readBeside(spec.confidencePath, "confidence");
    const std::string confName = "confidence " + spec.confidencePath;
    if (!isPngFile(spec.confidencePath) || conf.channels != 1 || !(conf.type == SampleType::U8 || conf.type == SampleType::U16))
      bad(where, confName + ": a confidence image is a gray 8/16-bit PNG (the vote weight of each pixel); this one has " +
                     std::to_string(conf.channels) + " channel(s) of " + sampleTypeName(conf.type));
    view.weight.resize(N);
    for (uint32_t y = 0; y < conf.height; ++y)
      for (uint32_t x = 0; x < conf.width; ++x)
        view.weight[size_t(y) * conf.width + x] =
            conf.type == SampleType::U8 ? conf.row<uint8_t>(y)[x] : conf.row<uint16_t>(y)[x];
  }

  if (!spec.normalPath.empty()) {
    const Image normal = readBeside(spec.normalPath, "normal");
    const std::string normalName = "normal " + spec.normalPath;
    if (!isPngFile(spec.normalPath) || normal.channels != 4 || normal.type != SampleType::U8)
      bad(where, normalName + ": a normal image is render-canonical's RGBA8 PNG; this one has " +
                     std::to_string(normal.channels) + " channel(s) of " + sampleTypeName(normal.type));
    view.faceAxis.assign(N, -1);
    // A pixel equal to the one before it (most are) takes its axis.
    uint32_t lastPixel = 0;
    int8_t lastAxis = -1;
    for (uint32_t y = 0; y < normal.height; ++y) {
      const uint8_t* normalRow = normal.pixels.data() + size_t(y) * normal.width * 4;
      for (uint32_t x = 0; x < normal.width; ++x) {
        const uint8_t* p = normalRow + size_t(x) * 4;
        uint32_t pixel;
        std::memcpy(&pixel, p, 4);
        if (lastAxis >= 0 && pixel == lastPixel) {
          view.faceAxis[size_t(y) * normal.width + x] = lastAxis;
          continue;
        }
        if (p[3] == 0) continue;
        int axis = -1, off = 0;
        for (int a = 0; a < 3; ++a)
          if (p[a] != 128) {
            axis = a;
            ++off;
          }
        if (off != 1 || (p[axis] != 0 && p[axis] != 255))
          bad(where, normalName + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                         ") is not an axis normal (components 0, 128 or 255, one of them not 128)");
        view.faceAxis[size_t(y) * normal.width + x] = int8_t(axis);
        lastPixel = pixel, lastAxis = int8_t(axis);
      }
    }
  }
  return out;
}

}  // namespace vox
