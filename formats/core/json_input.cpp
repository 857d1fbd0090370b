#include "formats/core/json_input.h"

#include <algorithm>
#include <string>
#include <unordered_set>
#include <vector>

#include "libvox/core/error.h"

namespace vox {

namespace {

using json = nlohmann::json;

/// nlohmann's DOM builder, with every object's keys checked as they are
/// read. A SAX wrapper rather than json::parse's callback: the callback
/// parser is super-linear in the document's size (a 22 MB document took 80x
/// as long as a plain parse), this costs about what the keys' copies cost.
/// The path of an object is put together only for the message.
class CheckedDomParser {
 public:
  CheckedDomParser(json& result, bool exceptions, const std::string& name) : dom_(result, exceptions), name_(name) {}

  bool null() { return value(), dom_.null(); }
  bool boolean(bool v) { return value(), dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return value(), dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return value(), dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const json::string_t& s) { return value(), dom_.number_float(v, s); }
  bool string(json::string_t& v) { return value(), dom_.string(v); }
  bool binary(json::binary_t& v) { return value(), dom_.binary(v); }
  bool start_object(std::size_t n) {
    open(true);
    return dom_.start_object(n);
  }
  bool key(json::string_t& k) {
    Frame& f = frames_[depth_ - 1];
    if (f.named(k)) duplicate(k);
    f.key = k;
    return dom_.key(k);
  }
  bool end_object() {
    --depth_;
    return dom_.end_object();
  }
  bool start_array(std::size_t n) {
    open(false);
    return dom_.start_array(n);
  }
  bool end_array() {
    --depth_;
    return dom_.end_array();
  }
  bool parse_error(std::size_t at, const std::string& token, const nlohmann::detail::exception& e) {
    return dom_.parse_error(at, token, e);
  }
  bool is_errored() const { return dom_.is_errored(); }

 private:
  // An open object or array. Frames are reused by depth, so the key lists
  // keep their capacity from one object to the next.
  struct Frame {
    bool object = false;
    size_t index = 0;                   // arrays: the element being read
    std::string key;                    // objects: the member being read
    std::vector<std::string> keys;      // objects: the keys named so far (few: searched in order) ...
    std::unordered_set<std::string> many;  // ... or, past kFew, hashed

    static constexpr size_t kFew = 24;
    // Whether `k` was named before; records it.
    bool named(const std::string& k) {
      if (!many.empty()) return !many.insert(k).second;
      if (std::find(keys.begin(), keys.end(), k) != keys.end()) return true;
      if (keys.size() < kFew) {
        keys.push_back(k);
      } else {
        many.insert(keys.begin(), keys.end());
        many.insert(k);
      }
      return false;
    }
  };

  // A value (scalar or the start of a container) begins in the innermost frame.
  void value() {
    if (depth_ > 0 && !frames_[depth_ - 1].object) ++frames_[depth_ - 1].index;
  }
  void open(bool object) {
    if (depth_ > 0 && !frames_[depth_ - 1].object) frames_[depth_ - 1].index++;
    if (frames_.size() == depth_) frames_.emplace_back();
    Frame& f = frames_[depth_++];
    f.object = object, f.index = 0, f.key.clear(), f.keys.clear(), f.many.clear();
  }

  [[noreturn]] void duplicate(const std::string& k) const {
    // The innermost object's path: each enclosing frame adds its member or element.
    std::string path;
    for (size_t d = 0; d + 1 < depth_; ++d) {
      const Frame& f = frames_[d];
      if (f.object)
        path += (path.empty() ? "" : ".") + f.key;
      else
        path += "[" + std::to_string(f.index - 1) + "]";
    }
    throw Error(ErrorKind::BadInput, name_ + ": duplicate key \"" + k + "\" in " +
                                         (path.empty() ? std::string("the top-level object") : path) +
                                         ": JSON keeps only one of the values; remove the other");
  }

  nlohmann::detail::json_sax_dom_parser<json> dom_;
  const std::string& name_;
  std::vector<Frame> frames_;
  size_t depth_ = 0;
};

json parse(std::string_view text, const std::string& name, bool exceptions) {
  json result;
  CheckedDomParser sax(result, exceptions, name);
  json::sax_parse(text.begin(), text.end(), &sax);
  if (sax.is_errored()) return json(json::value_t::discarded);
  return result;
}

}  // namespace

nlohmann::json parseJsonInput(std::string_view text, const std::string& name) { return parse(text, name, true); }

nlohmann::json parseJsonInputOrDiscarded(std::string_view text, const std::string& name) {
  return parse(text, name, false);
}

}  // namespace vox
