// vox diff of images (atlases, bitmaps, renders; PNG 8/16-bit, EXR), like
// OpenImageIO's idiff, and of a render against the reference image a
// block-map metadata.json carries for a view (`rgbBase64`).
#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <sstream>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/core/json_diff.h"
#include "formats/core/json_text.h"
#include "formats/image/atlas_meta.h"
#include "formats/image/image.h"
#include "formats/image/image_diff.h"
#include "formats/image/png_memory.h"
#include "libvox/core/error.h"
#include "tools/cli/cli.h"
#include "tools/cmds/diff_common.h"

namespace voxcli {

namespace {

vox::Image readImage(const std::string& path) {
  if (vox::isPngFile(path)) return vox::readPng(path);
  if (vox::isExrFile(path)) return vox::readExr(path);
  throw vox::Error(vox::ErrorKind::BadInput, path + ": not a PNG or EXR image");
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

std::string channelName(uint32_t channels, uint32_t c) {
  static const char* rgba[] = {"R", "G", "B", "A"};
  if (channels == 1) return "Y";
  if (channels == 2) return c == 0 ? "Y" : "A";
  return rgba[c];
}

// The atlas entries of both images (when they have one), and the voxel of a texel.
struct AtlasPair {
  std::optional<vox::AtlasImageInfo> a, b;
  std::string mismatch;  // why they cannot be compared texel for texel, if so
};

// Each entry is read and checked against its image by the reader info and
// verify-bijection use: an atlas whose size contradicts its layout is refused.
AtlasPair atlasInfos(const vox::Image& a, const vox::Image& b, const std::string& nameA, const std::string& nameB) {
  AtlasPair p;
  p.a = vox::atlasInfoOfImage(a, nameA);
  p.b = vox::atlasInfoOfImage(b, nameB);
  if (p.a.has_value() != p.b.has_value())
    p.mismatch = std::string("only ") + (p.a ? "A" : "B") + " is an atlas (has a " + vox::kAtlasTextKey + " entry)";
  else if (p.a && !(p.a->layout == p.b->layout))
    p.mismatch = "atlas layouts differ: " + p.a->layout.toJson() + " vs " + p.b->layout.toJson();
  else if (p.a && (p.a->content != p.b->content || p.a->format != p.b->format || p.a->layer != p.b->layer ||
                   p.a->classId != p.b->classId))
    p.mismatch = "atlas contents differ: " + vox::atlasInfoJson(*p.a).dump() + " vs " + vox::atlasInfoJson(*p.b).dump();
  return p;
}

bool isBitmap(const vox::AtlasImageInfo& i) {
  return i.content == vox::AtlasContent::Occupancy || i.content == vox::AtlasContent::Occupancy2;
}

// The voxel of pixel (x, y) of an atlas; for bitmaps, of the lowest differing
// bit of the byte (x, y).
std::optional<vox::Coord3> texelVoxel(const vox::AtlasImageInfo& info, const vox::Image& a, const vox::Image& b,
                                      uint32_t x, uint32_t y) {
  if (!isBitmap(info)) return info.layout.toVoxel(info.layer, x, y);
  const uint32_t perByte = info.content == vox::AtlasContent::Occupancy ? 8 : 4;
  const uint32_t bits = 8 / perByte;
  const uint8_t da = a.pixels[size_t(y) * a.width * a.channels + size_t(x) * a.channels];
  const uint8_t db = b.pixels[size_t(y) * b.width * b.channels + size_t(x) * b.channels];
  const uint8_t diff = da ^ db;
  for (uint32_t k = 0; k < perByte; ++k)
    if ((diff >> (k * bits)) & ((1u << bits) - 1)) return info.layout.toVoxel(info.layer, x * perByte + k, y);
  return info.layout.toVoxel(info.layer, x * perByte, y);
}

std::array<uint8_t, 3> parseBackground(const std::string& text) {
  if (text.empty()) return {135, 207, 235};
  const auto t = parseTriple(text, "--background");
  for (uint32_t v : t)
    if (v > 255) throw vox::Error(vox::ErrorKind::Usage, "--background " + text + ": expected R,G,B in 0..255");
  return {uint8_t(t[0]), uint8_t(t[1]), uint8_t(t[2])};
}

nlohmann::json pixelValuesJson(const vox::Image& img, uint32_t x, uint32_t y) {
  nlohmann::json v = nlohmann::json::array();
  for (uint32_t c = 0; c < img.channels; ++c) v.push_back(vox::sampleAt(img, x, y, c));
  return v;
}

std::string pixelValuesText(const vox::Image& img, uint32_t x, uint32_t y) {
  std::string s;
  for (uint32_t c = 0; c < img.channels; ++c) s += (c ? ", " : "") + num(vox::sampleAt(img, x, y, c));
  return s;
}

std::string describeImage(const vox::Image& img) {
  return std::to_string(img.width) + " x " + std::to_string(img.height) + ", " + std::to_string(img.channels) +
         " channel" + (img.channels == 1 ? "" : "s") + " " + vox::sampleTypeName(img.type);
}

double percent(uint64_t n, uint64_t of) { return of ? 100.0 * double(n) / double(of) : 0.0; }

// Compares two decoded images and reports; shared by files and references.
int compareAndReport(const vox::Image& a, const vox::Image& b, const std::string& nameB, const DiffOptions& o,
                     Run& run, const std::string& kind, nlohmann::json extra) {
  const AtlasPair atlas = atlasInfos(a, b, o.a, nameB);
  vox::ImageDiffOptions io;
  // 32-bit integer samples: one unit is 2.3e-10 once normalised, far under
  // idiff's 1e-6, so the defaults become 0 (any difference fails).
  const bool u32 = a.type == vox::SampleType::U32 && b.type == vox::SampleType::U32;
  io.failThreshold = o.fail.value_or(u32 ? 0.0 : 1e-6);
  io.warnThreshold = o.warn.value_or(u32 ? 0.0 : 1e-6);
  io.failPercent = o.failPercent, io.warnPercent = o.warnPercent;
  io.hardFail = o.hardFail, io.hardWarn = o.hardWarn;
  io.background = parseBackground(o.background);
  io.maskNonZero = atlas.a.has_value() || atlas.b.has_value();
  io.threads = o.threads;
  const vox::ImageDiff d = vox::diffImages(a, b, io);
  const bool failed = d.verdict == vox::ImageVerdict::Fail || !atlas.mismatch.empty();
  const char* verdict = failed ? "FAILURE" : vox::imageVerdictName(d.verdict);

  std::optional<vox::Coord3> maxVoxel, firstVoxel;
  if (atlas.a && atlas.mismatch.empty() && d.incompatible.empty()) {
    if (d.pixelsDiffering) maxVoxel = texelVoxel(*atlas.a, a, b, d.maxX, d.maxY);
    if (d.firstDiffering) firstVoxel = texelVoxel(*atlas.a, a, b, (*d.firstDiffering)[0], (*d.firstDiffering)[1]);
  }
  if (!o.diffImage.empty() && d.incompatible.empty()) {
    const std::string tmp = run.output(o.diffImage);
    if (vox::hasExtension(o.diffImage, ".exr"))
      vox::writeExr(vox::differenceImage(a, b, o.diffScale, vox::SampleType::F32), tmp);
    else
      vox::writePng(vox::differenceImage(a, b, o.diffScale), tmp);
  } else if (!o.diffImage.empty()) {
    // No pixel pairs to draw; an older image under that name would pass for this run's.
    run.note("warning: no difference image written (" + d.incompatible + "); " + o.diffImage +
             (std::filesystem::exists(o.diffImage) ? " is an earlier run's, left as it was" : " does not exist"));
    run.counts()["diff_image_written"] = false;
  }

  if (o.json) {
    nlohmann::json j = {{"kind", kind},           {"a", o.a},
                        {"b", nameB},             {"verdict", verdict},
                        {"same", d.incompatible.empty() && atlas.mismatch.empty() && d.pixelsDiffering == 0}};
    for (auto& [k, v] : extra.items()) j[k] = v;
    j["image_a"] = describeImage(a), j["image_b"] = describeImage(b);
    if (!atlas.mismatch.empty()) j["atlas_mismatch"] = atlas.mismatch;
    if (atlas.a) j["atlas"] = vox::atlasInfoJson(*atlas.a);
    if (!d.incompatible.empty()) {
      j["incompatible"] = d.incompatible;
    } else {
      auto finiteOrNull = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
      j["width"] = d.width, j["height"] = d.height, j["channels_compared"] = d.channels;
      j["pixels"] = d.pixels, j["pixels_differing"] = d.pixelsDiffering;
      j["warn"] = {{"threshold", io.warnThreshold}, {"percent", io.warnPercent}, {"pixels", d.warnPixels}};
      j["fail"] = {{"threshold", io.failThreshold}, {"percent", io.failPercent}, {"pixels", d.failPixels}};
      j["hardfail"] = finiteOrNull(io.hardFail), j["hardwarn"] = finiteOrNull(io.hardWarn);
      j["mean_error"] = d.meanError, j["mse"] = d.mse, j["rms_error"] = d.rmsError;
      j["psnr"] = finiteOrNull(d.psnr);  // null: infinite (equal images)
      j["ssim"] = d.ssim ? nlohmann::json(*d.ssim) : nlohmann::json(nullptr);
      j["ssim_window"] = "8x8 uniform, per colour channel";
      j["max_error"] = d.maxError;
      if (d.pixelsDiffering) {
        nlohmann::json m = {{"pixel", {d.maxX, d.maxY}},
                            {"channel", channelName(d.channels, d.maxChannel)},
                            {"a", pixelValuesJson(a, d.maxX, d.maxY)},
                            {"b", pixelValuesJson(b, d.maxX, d.maxY)}};
        if (maxVoxel) m["voxel"] = coordJson(*maxVoxel);
        j["max_error_at"] = m;
        const auto [fx, fy] = *d.firstDiffering;
        nlohmann::json f = {{"pixel", {fx, fy}}, {"a", pixelValuesJson(a, fx, fy)}, {"b", pixelValuesJson(b, fx, fy)}};
        if (firstVoxel) f["voxel"] = coordJson(*firstVoxel);
        j["first_difference"] = f;
      }
      j["mask_agreement"] = d.maskAgreeFraction();
      j["mask_pixels_agreeing"] = d.maskAgree;
      j["mask_source"] = d.maskSource;
      if (!o.diffImage.empty()) j["diff_image"] = o.diffImage;
    }
    std::cout << vox::jsonText(j, 2) << "\n";
  } else {
    std::ostringstream s;
    s << "Comparing \"" << o.a << "\" and \"" << nameB << "\" (" << kind;
    if (atlas.a) s << " " << vox::atlasInfoJson(*atlas.a)["content"].get<std::string>();
    s << ", " << describeImage(a);
    if (b.channels != a.channels || b.type != a.type) s << " vs " << describeImage(b);
    s << ")\n";
    if (!atlas.mismatch.empty()) s << "  " << atlas.mismatch << "\n";
    if (!d.incompatible.empty()) {
      s << "  " << d.incompatible << "\n";
    } else {
      s << "  Mean error = " << num(d.meanError) << "  RMS error = " << num(d.rmsError) << "  MSE = " << num(d.mse)
        << "\n  Peak SNR = " << (std::isfinite(d.psnr) ? num(d.psnr) + " dB" : std::string("inf"))
        << "  SSIM = " << (d.ssim ? num(*d.ssim) : std::string("n/a (image under 8x8)")) << "\n";
      s << "  Max error  = " << num(d.maxError);
      if (d.pixelsDiffering) {
        s << " @ (" << d.maxX << ", " << d.maxY << ", " << channelName(d.channels, d.maxChannel) << ")";
        if (maxVoxel) s << " = voxel " << vox::toString(*maxVoxel);
        s << "  values are " << pixelValuesText(a, d.maxX, d.maxY) << " vs " << pixelValuesText(b, d.maxX, d.maxY);
      }
      s << "\n";
      if (d.firstDiffering) {
        const auto [fx, fy] = *d.firstDiffering;
        s << "  first differing pixel (" << fx << ", " << fy << ")";
        if (firstVoxel) s << " = voxel " << vox::toString(*firstVoxel);
        s << "  values are " << pixelValuesText(a, fx, fy) << " vs " << pixelValuesText(b, fx, fy) << "\n";
      }
      char line[160];
      auto pixels = [](uint64_t n) { return n == 1 ? "pixel" : "pixels"; };
      std::snprintf(line, sizeof line, "  %llu %s (%.3g%%) %s\n", (unsigned long long)d.pixelsDiffering,
                    pixels(d.pixelsDiffering), percent(d.pixelsDiffering, d.pixels),
                    d.pixelsDiffering == 1 ? "differs" : "differ");
      s << line;
      std::snprintf(line, sizeof line, "  %llu %s (%.3g%%) over %g (warn)\n", (unsigned long long)d.warnPixels,
                    pixels(d.warnPixels), percent(d.warnPixels, d.pixels), io.warnThreshold);
      s << line;
      std::snprintf(line, sizeof line, "  %llu %s (%.3g%%) over %g (fail)\n", (unsigned long long)d.failPixels,
                    pixels(d.failPixels), percent(d.failPixels, d.pixels), io.failThreshold);
      s << line;
      std::snprintf(line, sizeof line, "  hit/miss mask agrees on %.4f%% of pixels (%s)\n",
                    100.0 * d.maskAgreeFraction(), d.maskSource.c_str());
      s << line;
      if (!o.diffImage.empty()) s << "  difference image: " << o.diffImage << "\n";
    }
    s << verdict << "\n";
    std::cout << s.str();
  }
  return failed ? kExitCheckFailed : kExitOk;
}

// Standard base64 (RFC 4648), padding optional; whitespace skipped.
std::vector<uint8_t> decodeBase64(const std::string& text, const std::string& context) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;
    if (c == '/' || c == '_') return 63;
    return -1;
  };
  std::vector<uint8_t> out;
  out.reserve(text.size() * 3 / 4);
  uint32_t acc = 0;
  int bits = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '=') break;
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    const int v = value(c);
    if (v < 0)
      throw vox::Error(vox::ErrorKind::BadInput, context + ": not base64 (character " + std::to_string(i) + ")");
    acc = (acc << 6) | uint32_t(v), bits += 6;
    if (bits >= 8) bits -= 8, out.push_back(uint8_t(acc >> bits));
  }
  return out;
}

std::string atlasKind(const vox::Image& a, const vox::Image& b) {
  return a.textValue(vox::kAtlasTextKey).empty() && b.textValue(vox::kAtlasTextKey).empty() ? "images" : "atlases";
}

// --diff-image is written in the format its name says: refused before the
// work when that is neither (PNG bytes went into a .exr).
void checkDiffImageName(const DiffOptions& o) {
  if (!o.diffImage.empty() && !vox::hasExtension(o.diffImage, ".png") && !vox::hasExtension(o.diffImage, ".exr"))
    throw vox::Error(vox::ErrorKind::Usage, "--diff-image " + o.diffImage +
                                                ": the difference image is written as .png (RGB8) or .exr (float); "
                                                "name it so");
}

}  // namespace

int diffImageFiles(const DiffOptions& o, Run& run) {
  checkDiffImageName(o);
  auto second = std::async(std::launch::async, [&] { return readImage(o.b); });
  vox::Image a;
  try {
    a = readImage(o.a);
  } catch (...) {
    try {
      second.get();
    } catch (...) {
    }
    throw;
  }
  const vox::Image b = second.get();
  // An EXR's other channels (a depth Z beside R, G, B...) are not compared: say so.
  nlohmann::json notCompared = nlohmann::json::object();
  for (const auto& [path, image] : {std::pair<const std::string&, const vox::Image&>{o.a, a}, {o.b, b}}) {
    if (image.channelsNotRead.empty()) continue;
    std::string names;
    for (const std::string& c : image.channelsNotRead) names += (names.empty() ? "" : ", ") + c;
    run.note("warning: " + path + ": " + counted(image.channelsNotRead.size(), "channel", "channels") + " not compared (" +
             names + "); vox diff compares R, G, B and A");
    notCompared[path] = image.channelsNotRead;
  }
  if (!notCompared.empty()) run.counts()["channels_not_compared"] = notCompared;
  return compareAndReport(a, b, o.b, o, run, atlasKind(a, b), nlohmann::json::object());
}

int diffRenderReference(const DiffOptions& o, Run& run) {
  checkDiffImageName(o);
  const nlohmann::json meta = vox::parseJsonDocument(vox::readFileBytes(o.b), o.b);
  if (!meta.is_object() || !meta.contains("views") || !meta["views"].is_array())
    throw vox::Error(vox::ErrorKind::BadInput, o.b + ": no \"views\" array (expected the block-map format's metadata.json)");
  const nlohmann::json& views = meta["views"];
  std::optional<size_t> pick;
  int wanted = -1;
  if (o.view) {
    wanted = *o.view;
    for (size_t i = 0; i < views.size() && !pick; ++i)
      if (views[i].is_object() && views[i].contains("index") && views[i]["index"].is_number_integer() &&
          views[i]["index"].get<int64_t>() == wanted)
        pick = i;
    if (!pick && wanted >= 0 && size_t(wanted) < views.size() &&
        !(views[size_t(wanted)].is_object() && views[size_t(wanted)].contains("index")))
      pick = size_t(wanted);
    if (!pick)
      throw vox::Error(vox::ErrorKind::BadInput, o.b + ": no view with index " + std::to_string(wanted) + " (" +
                                                     counted(views.size(), "view", "views") + ")");
  } else {
    std::vector<size_t> withImage;
    for (size_t i = 0; i < views.size(); ++i)
      if (views[i].is_object() && views[i].contains("rgbBase64")) withImage.push_back(i);
    if (withImage.size() != 1)
      throw vox::Error(vox::ErrorKind::Usage, o.b + " has " + std::to_string(withImage.size()) +
                                                  " views with an rgbBase64 image: choose one with --view N");
    pick = withImage[0];
  }
  const nlohmann::json& view = views[*pick];
  const std::string where = o.b + ": views[" + std::to_string(*pick) + "].rgbBase64";
  if (!view.contains("rgbBase64") || !view["rgbBase64"].is_string())
    throw vox::Error(vox::ErrorKind::BadInput, where + " is missing: this view carries no reference image");
  std::string text = view["rgbBase64"].get<std::string>();
  if (text.rfind("data:", 0) == 0) {  // a data URI: data:image/png;base64,....
    const size_t comma = text.find(',');
    if (comma == std::string::npos) throw vox::Error(vox::ErrorKind::BadInput, where + ": a data URI without ','");
    text = text.substr(comma + 1);
  }
  const std::vector<uint8_t> png = decodeBase64(text, where);
  const vox::Image reference = vox::readPngMemory(png.data(), png.size(), where);
  const vox::Image render = readImage(o.a);
  nlohmann::json extra = {{"view", view.contains("index") ? view["index"] : nlohmann::json(*pick)}};
  if (view.contains("id")) extra["view_id"] = view["id"];
  return compareAndReport(render, reference, o.b + " view " + extra["view"].dump(), o, run, "render vs reference",
                          extra);
}

}  // namespace voxcli
