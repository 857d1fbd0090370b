// vox diff A B: compares two artefacts in the voxel's terms (docs/diff.md),
// like OpenImageIO's idiff for images: exit 0 when they are the same (or
// within the tolerances), 1 when they differ, 2 when the two files are of
// different kinds (or the options make no sense), 3 when an input cannot be
// read. The kind is sniffed from the content: scenes and pyramids (.vdb),
// page files (.vpk), images (.png, .exr), JSON (reports, touched sets), and a
// render against a block-map metadata.json's reference image (--view N).
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <optional>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/core/json_text.h"
#include "formats/image/image.h"
#include "formats/pagefile/pagefile.h"
#include "formats/vdb/scene_vdb.h"
#include "libvox/core/error.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/dispatch.h"
#include "tools/cli/number_checks.h"
#include "tools/cmds/diff_common.h"

namespace voxcli {

namespace {

// What is compared: a kind of file, or a render against a metadata.json's
// reference image. Bits, so that an option names every kind it applies to.
enum class DiffKind : unsigned { Scene = 1, Pages = 2, Image = 4, Json = 8, RenderReference = 16 };

const char* kindText(DiffKind k) {
  switch (k) {
    case DiffKind::Scene: return "a scene or pyramid (.vdb)";
    case DiffKind::Pages: return "a page file (.vpk)";
    case DiffKind::Image: return "an image (.png, .exr)";
    case DiffKind::Json: return "a JSON file";
    case DiffKind::RenderReference: return "a render compared with a metadata.json";
  }
  return "?";
}

const char* kindsPlural(DiffKind k) {
  switch (k) {
    case DiffKind::Scene: return "scenes and pyramids (.vdb)";
    case DiffKind::Pages: return "page files (.vpk)";
    case DiffKind::Image: return "images (.png, .exr)";
    case DiffKind::Json: return "JSON files";
    case DiffKind::RenderReference: return "a render compared with a metadata.json (vox diff RENDER.png metadata.json --view N)";
  }
  return "?";
}

// The options that apply to some kinds only, and those kinds; every other
// option (--json, --threads, --report, --depfile...) applies to all. One
// table, so that an option of another kind is always a usage error (docs/diff.md).
struct ScopedOption {
  const char* name;
  unsigned kinds;
};
constexpr unsigned kScene = unsigned(DiffKind::Scene), kPages = unsigned(DiffKind::Pages),
                   kImages = unsigned(DiffKind::Image) | unsigned(DiffKind::RenderReference),
                   kJson = unsigned(DiffKind::Json), kRenderReference = unsigned(DiffKind::RenderReference);
constexpr ScopedOption kScopedOptions[] = {
    {"--level", kScene},           {"--ignore-sources", kScene},        {"--votes-tolerance", kScene},
    {"--color-tolerance", kScene | kPages},
    {"--fail", kImages},           {"--warn", kImages},                 {"--failpercent", kImages},
    {"--warnpercent", kImages},    {"--hardfail", kImages},             {"--hardwarn", kImages},
    {"--diff-image", kImages},     {"--diff-scale", kImages},           {"--background", kImages},
    {"--view", kRenderReference},
    {"--rel-tolerance", kJson},    {"--ignore-key", kJson},             {"--no-default-ignores", kJson},
};

/// "scenes and pyramids (.vdb) and page files (.vpk)": the kinds of a bit set.
std::string kindsList(unsigned kinds) {
  std::vector<std::string> names;
  for (DiffKind k : {DiffKind::Scene, DiffKind::Pages, DiffKind::Image, DiffKind::Json, DiffKind::RenderReference})
    // A render against a reference is an image comparison: images name it.
    if ((kinds & unsigned(k)) && !(k == DiffKind::RenderReference && (kinds & unsigned(DiffKind::Image))))
      names.push_back(kindsPlural(k));
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) s += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return s;
}

/// Throws vox::Error (Usage) naming the first option given that does not apply to `kind`.
void refuseOptionsOfOtherKinds(const CLI::App& app, DiffKind kind) {
  for (const ScopedOption& option : kScopedOptions)
    if (app.count(option.name) > 0 && !(option.kinds & unsigned(kind)))
      throw vox::Error(vox::ErrorKind::Usage, std::string(option.name) + " applies to " + kindsList(option.kinds) +
                                                  ", not to " + kindText(kind));
}

bool looksLikeJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char c = 0;
  while (in.get(c))
    if (!std::isspace(static_cast<unsigned char>(c))) return c == '{' || c == '[';
  return false;
}

DiffKind kindOf(const std::string& path) {
  vox::requireRegularFile(path);  // missing, a directory or FIFO, unreadable: named before the sniffing
  if (vox::looksLikeVdb(path)) return DiffKind::Scene;
  if (vox::pagefile::looksLikePageFile(path)) return DiffKind::Pages;
  if (vox::isPngFile(path) || vox::isExrFile(path)) return DiffKind::Image;
  if (vox::hasExtension(path, ".json") || looksLikeJson(path)) return DiffKind::Json;
  throw vox::Error(vox::ErrorKind::BadInput,
                   path + ": not a file vox diff reads (expected a scene or pyramid .vdb, a page file .vpk, a "
                          "PNG or EXR image, or JSON; the content decides, not the name)");
}

struct DiffCommand {
  DiffOptions o;
  CommonOptions common;
  CLI::App* app = nullptr;
};

/// The `kind` of --json for a comparison of this kind ("scene", "images"...;
/// the reports name scenes "pyramid" and images "atlases" when they are).
const char* kindKey(DiffKind k) {
  switch (k) {
    case DiffKind::Scene: return "scene";
    case DiffKind::Pages: return "pages";
    case DiffKind::Image: return "images";
    case DiffKind::Json: return "json";
    case DiffKind::RenderReference: return "render vs reference";
  }
  return "?";
}

int compare(DiffCommand& c, Run& run, std::optional<DiffKind>& known) {
  DiffOptions& o = c.o;
  const DiffKind ka = kindOf(o.a), kb = kindOf(o.b);
  const DiffKind kind = ka == DiffKind::Image && kb == DiffKind::Json ? DiffKind::RenderReference : ka;
  if (kind != DiffKind::RenderReference && ka != kb)
    throw vox::Error(vox::ErrorKind::Usage, o.a + " is " + kindText(ka) + " but " + o.b + " is " + kindText(kb) +
                                                ": vox diff compares two files of one kind (or a render with a "
                                                "metadata.json and --view N)");
  known = kind;
  // Options that belong to another kind are refused rather than ignored.
  refuseOptionsOfOtherKinds(*c.app, kind);
  int code = kExitOk;
  switch (kind) {
    case DiffKind::RenderReference: code = diffRenderReference(o, run); break;
    case DiffKind::Scene: code = diffSceneFiles(o); break;
    case DiffKind::Pages: code = diffPageFiles(o); break;
    case DiffKind::Image: code = diffImageFiles(o, run); break;
    case DiffKind::Json: code = diffJsonFiles(o); break;
  }
  return code;
}

int runDiff(DiffCommand& c) {
  DiffOptions& o = c.o;
  Run run("diff", c.common);
  o.threads = run.threads();
  std::optional<DiffKind> kind;  // once both files are known to be of one kind
  int code = kExitOk;
  try {
    run.input(o.a);
    run.input(o.b);
    code = compare(c, run, kind);
  } catch (const vox::Error& e) {
    // --json promises one object with "same" and "kind", refusals (exit 2)
    // and unreadable inputs (exit 3) included; the message goes to stderr too.
    if (o.json && (e.kind == vox::ErrorKind::Usage || e.kind == vox::ErrorKind::BadInput)) {
      const nlohmann::json j = {{"kind", kind ? nlohmann::json(kindKey(*kind)) : nlohmann::json(nullptr)},
                                {"a", o.a},
                                {"b", o.b},
                                {"same", false},
                                {"error", messageFor(e)},
                                {"exit_code", exitCodeFor(e.kind)}};
      std::cout << vox::jsonText(j, 2) << "\n";
    }
    throw;
  }
  return run.finish(code);
}

}  // namespace

Command registerDiff(CLI::App& root) {
  auto c = std::make_shared<DiffCommand>();
  DiffOptions& o = c->o;
  CLI::App* cmd = root.add_subcommand(
      "diff",
      "Compare two scenes, pyramids, page files, images (atlases, bitmaps, renders) or JSON files; exit 0 same, 1 "
      "differs, 2 different kinds, 3 unreadable (docs/diff.md)");
  c->app = cmd;
  cmd->add_option("a", o.a, "First file (or the render, with a metadata.json as the second)")->required();
  cmd->add_option("b", o.b, "Second file (the golden / reference one)")->required();
  cmd->add_flag("--json", o.json, "Print the comparison as JSON on stdout");
  cmd->add_flag("--ignore-sources", o.ignoreSources, "Scenes: do not compare the recorded source files");
  cmd->add_option("--level", o.level,
                  "Pyramids: compare level N only (a plain scene on either side is taken as that level, e.g. a "
                  "mip --split file)")
      ->type_name("N");
  cmd->add_option("--votes-tolerance", o.votesTolerance,
                  "Scenes: votes of one class may differ by this many per voxel")
      ->type_name("UINT");  // an unsigned integer: "nan" and "-1" do not convert
  cmd->add_option("--color-tolerance", o.colorTolerance,
                  "Scenes: colour channels (linear, 0..1) may differ by this much; page files: x 255 in sRGB8 units")
      ->check(FiniteInRange(0.0, 1.0));
  cmd->add_option("--fail", o.fail, "Images: a pixel fails when a channel differs by more than this (idiff; default 1e-6, 0 for 32-bit samples)")
      ->check(FiniteNonNegative);
  cmd->add_option("--failpercent", o.failPercent, "Images: allow this percentage of failing pixels (default 0)")
      ->check(FiniteInRange(0.0, 100.0));
  cmd->add_option("--hardfail", o.hardFail, "Images: fail if any one pixel differs by more than this (default inf)")
      ->check(NonNegativeOrInfinity);
  cmd->add_option("--warn", o.warn, "Images: warning threshold (idiff; default 1e-6, 0 for 32-bit samples)")
      ->check(FiniteNonNegative);
  cmd->add_option("--warnpercent", o.warnPercent, "Images: allow this percentage of warnings (default 0)")
      ->check(FiniteInRange(0.0, 100.0));
  cmd->add_option("--hardwarn", o.hardWarn, "Images: warn if any one pixel differs by more than this (default inf)")
      ->check(NonNegativeOrInfinity);
  cmd->add_option("--diff-image", o.diffImage, "Images: write |A - B| here, an RGB8 PNG (.png) or float EXR (.exr)");
  cmd->add_option("--diff-scale", o.diffScale, "Images: multiply the difference image by this (default 1)")
      ->check(FinitePositive);
  cmd->add_option("--background", o.background,
                  "Images without alpha: the miss colour R,G,B (0..255) for the hit/miss mask (default 135,207,235, "
                  "the shaded sky)");
  cmd->add_option("--view", o.view, "Render vs metadata.json: the view's index whose rgbBase64 image is the reference");
  cmd->add_option("--rel-tolerance", o.relTolerance, "JSON: numbers may differ by this fraction of the larger")
      ->check(FiniteNonNegative);
  cmd->add_option("--ignore-key", o.ignoreKeys, "JSON: also skip keys matching this pattern ('*' wildcard); repeatable")
      ->allow_extra_args(false);  // one pattern per --ignore-key, so a file name after it stays a file
  cmd->add_flag("--no-default-ignores", o.noDefaultIgnores,
                "JSON: compare timings and paths too (default: seconds, *_seconds, *_per_second, *_per_s, threads, "
                "argv, inputs, outputs, scene, file, path are skipped)");
  addCommonOptions(*cmd, c->common);
  return {cmd, [c] { return runDiff(*c); }};
}

}  // namespace voxcli
