#include "formats/core/json_input.h"

#include <unordered_set>
#include <vector>

#include "libvox/core/error.h"

namespace vox {

namespace {

/// Follows the parser through the document: the path of every open object or
/// array, and the keys each open object has named so far.
class DuplicateKeys {
 public:
  explicit DuplicateKeys(const std::string& name) : name_(name) {}

  bool operator()(int /*depth*/, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        open_.push_back({event == Event::object_start, childPath(), {}, {}, 0});
        break;
      case Event::key: {
        Open& o = open_.back();
        std::string key = parsed.get<std::string>();
        if (!o.keys.insert(key).second)
          throw Error(ErrorKind::BadInput, name_ + ": duplicate key \"" + key + "\" in " +
                                               (o.path.empty() ? std::string("the top-level object") : o.path) +
                                               ": JSON keeps only one of the values; remove the other");
        o.key = std::move(key);
        break;
      }
      case Event::object_end:
      case Event::array_end:
        open_.pop_back();
        if (!open_.empty() && !open_.back().object) ++open_.back().index;
        break;
      case Event::value:
        if (!open_.empty() && !open_.back().object) ++open_.back().index;
        break;
    }
    return true;
  }

 private:
  struct Open {
    bool object;
    std::string path;
    std::unordered_set<std::string> keys;
    std::string key;  // the member being read (objects)
    size_t index;     // the element being read (arrays)
  };

  // The path of a value that starts now: "" for the document itself.
  std::string childPath() const {
    if (open_.empty()) return "";
    const Open& o = open_.back();
    if (!o.object) return o.path + "[" + std::to_string(o.index) + "]";
    return o.path.empty() ? o.key : o.path + "." + o.key;
  }

  const std::string& name_;
  std::vector<Open> open_;
};

nlohmann::json parse(std::string_view text, const std::string& name, bool exceptions) {
  DuplicateKeys check(name);
  return nlohmann::json::parse(text.begin(), text.end(),
                               [&check](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
                                 return check(depth, event, parsed);
                               },
                               exceptions);
}

}  // namespace

nlohmann::json parseJsonInput(std::string_view text, const std::string& name) { return parse(text, name, true); }

nlohmann::json parseJsonInputOrDiscarded(std::string_view text, const std::string& name) {
  return parse(text, name, false);
}

}  // namespace vox
