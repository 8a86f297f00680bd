#include "scene/scene_loader.h"

#include <fcntl.h>
#include <simdjson.h>
#include <unistd.h>

#include <array>
#include <bitset>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <future>
#include <glm/geometric.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <sstream>
#include <system_error>

#include "core/sha256.h"
#include "rt_schema.h"

namespace rt {
namespace {

namespace od = simdjson::ondemand;
using Json = nlohmann::json;

// |dot(direction, +Y)| above this means the camera looks straight up or down
// and its right vector would be undefined (docs/render-model.md section 1).
constexpr double kMaxVerticalAlignment = 0.9999;

// The shortest text that reads back as `value` ("1e+39", "-1000001"), so a
// message never rounds a rejected number onto the limit.
std::string formatNumber(double value) {
  std::array<char, 32> text{};
  const auto end = std::to_chars(text.data(), text.data() + text.size(), value).ptr;
  return {text.data(), end};
}

// The renderers work in float: beyond schema::kSceneMaxMagnitude squares and
// sums of scene numbers lose the scene (1e39 is already infinite), below
// kSceneMinLength a length vanishes next to the coordinates
// (docs/render-model.md section 1).
// Appended piece by piece: `"[" + std::string&&` draws a false -Wrestrict
// from GCC 12 where it inlines the concatenation (the profile build does).
std::string range(double low, double high) {
  std::string text = "[";
  text += formatNumber(low);
  text += ", ";
  text += formatNumber(high);
  text += "]";
  return text;
}
std::string magnitudeRange() { return range(-schema::kSceneMaxMagnitude, schema::kSceneMaxMagnitude); }
std::string lengthRange() { return range(schema::kSceneMinLength, schema::kSceneMaxMagnitude); }

// Where a value sits in the document: a chain of stack objects, turned into
// "spheres[3].position[1]" only when a message needs it, so the million
// spheres of a large scene build no path strings.
struct Location {
  const Location* parent = nullptr;
  std::string_view key;  // an object member's name, or empty
  std::size_t index = 0;
  bool element = false;  // an array element: `index` applies

  Location member(std::string_view name) const { return {this, name, 0, false}; }
  Location at(std::size_t i) const { return {this, {}, i, true}; }

  std::string str() const {
    std::string text = parent != nullptr ? parent->str() : std::string();
    if (element) return text + "[" + std::to_string(index) + "]";
    if (key.empty()) return text;
    return text.empty() ? std::string(key) : text + "." + std::string(key);
  }
};

// A rule of the scene broken; parseScene adds the file name.
struct Refusal {
  std::string path;
  std::string reason;
};

[[noreturn]] void fail(const Location& at, const std::string& reason) { throw Refusal{at.str(), reason}; }

// The parser refused the text where the loader looked: the message is made
// after nlohmann has read the text again (see parseScene).
struct SyntaxFault {
  std::string path;
  simdjson::error_code code;
};

template <typename T>
T take(simdjson::simdjson_result<T>&& result, const Location& at) {
  T value{};
  if (const auto code = std::move(result).get(value); code != simdjson::SUCCESS) throw SyntaxFault{at.str(), code};
  return value;
}

// The names nlohmann's type_name() gives, which the messages always used.
const char* typeName(od::json_type type) {
  switch (type) {
    case od::json_type::array: return "array";
    case od::json_type::object: return "object";
    case od::json_type::number: return "number";
    case od::json_type::string: return "string";
    case od::json_type::boolean: return "boolean";
    case od::json_type::null: return "null";
    default: return "value";  // a kind newer simdjson releases may add
  }
}

od::json_type typeOf(od::value& v, const Location& at) { return take(v.type(), at); }

double number(od::value& v, const Location& at) {
  const od::json_type type = typeOf(v, at);
  if (type != od::json_type::number) fail(at, std::string("expected a number, got ") + typeName(type));
  const double d = take(v.get_double(), at);
  if (!std::isfinite(d)) fail(at, "not a finite number");
  return d;
}

// Exactly three finite numbers. The count is judged before the elements, as
// a whole-array rule: an element's fault is held until the count is known.
glm::dvec3 vector(od::value& v, const Location& at) {
  constexpr const char* shape = "expected an array of 3 numbers";
  if (typeOf(v, at) != od::json_type::array) fail(at, shape);
  glm::dvec3 out{0.0};
  std::size_t count = 0;
  std::optional<Refusal> firstFault;
  for (auto item : take(v.get_array(), at)) {
    od::value element = take(std::move(item), at);
    if (count < 3) {
      try {
        out[static_cast<int>(count)] = number(element, at.at(count));
      } catch (const Refusal& r) {
        if (!firstFault) firstFault = r;
      }
    }
    ++count;
  }
  if (count != 3) fail(at, shape);
  if (firstFault) throw *firstFault;
  return out;
}

// A number whose magnitude is at most kSceneMaxMagnitude.
double bounded(double value, const Location& at) {
  if (std::abs(value) > schema::kSceneMaxMagnitude) fail(at, formatNumber(value) + " is outside " + magnitudeRange());
  return value;
}

// A position or direction: every component bounded.
glm::dvec3 boundedVector(od::value& v, const Location& at) {
  const glm::dvec3 u = vector(v, at);
  for (std::size_t i = 0; i < 3; ++i) bounded(u[static_cast<int>(i)], at.at(i));
  return u;
}

glm::vec3 color(od::value& v, const Location& at) {
  const glm::dvec3 c = vector(v, at);
  for (std::size_t i = 0; i < 3; ++i) {
    const double component = c[static_cast<int>(i)];
    if (component < 0.0 || component > 1.0) fail(at.at(i), "color component outside [0, 1]");
  }
  return glm::vec3(c);
}

// Walks one JSON object, handing each member to `onMember(index of its key
// in keys, value, location)`. A key outside `keys` is refused (a typo must
// not be ignored silently), and so is a key given twice. Returns which keys
// were present.
template <std::size_t N, typename OnMember>
std::bitset<N> readObject(od::object object, const Location& at, const std::array<std::string_view, N>& keys,
                          OnMember&& onMember) {
  std::bitset<N> seen;
  for (auto item : object) {
    od::field field = take(std::move(item), at);
    const std::string_view key = take(field.unescaped_key(), at);
    const Location where = at.member(key);
    std::size_t i = 0;
    while (i < N && keys[i] != key) ++i;
    if (i == N) fail(where, "unknown key");
    if (seen[i]) fail(where, "duplicate key");
    seen[i] = true;
    od::value value = field.value();
    onMember(i, value, where);
  }
  return seen;
}

od::object objectOf(od::value& v, const Location& at) {
  const od::json_type type = typeOf(v, at);
  if (type != od::json_type::object) fail(at, std::string("expected an object, got ") + typeName(type));
  return take(v.get_object(), at);
}

template <std::size_t N>
void requireMembers(const std::bitset<N>& seen, const Location& at, const std::array<std::string_view, N>& keys,
                    std::initializer_list<std::size_t> required) {
  for (const std::size_t i : required) {
    if (!seen[i]) fail(at.member(keys[i]), "missing required field");
  }
}

// A direction normalised; one shorter than kSceneMinLength has no reliable
// direction (its squares underflow), so it is refused like a zero one.
glm::dvec3 unitOrFail(glm::dvec3 v, const Location& at) {
  const double length = glm::length(v);
  if (length == 0.0) fail(at, "zero-length direction");
  if (!(length >= schema::kSceneMinLength)) {
    fail(at,
         "direction of length " + formatNumber(length) + " is shorter than " + formatNumber(schema::kSceneMinLength));
  }
  return v / length;
}

// The rules between the camera's members, once all are read.
void checkCamera(CameraSpec& c, const std::optional<glm::dvec3>& forward, const Location& at) {
  if (forward) c.forward = unitOrFail(*forward, at.member("forward"));
  if (!forward && !c.focusPoint) fail(at.member("forward"), "missing: give forward or focusPoint");
  if (c.orbits() && !c.focusPoint) fail(at.member("orbitVelocity"), "a non-zero orbitVelocity needs a focusPoint");
  if (c.focusPoint && *c.focusPoint == c.position) fail(at.member("focusPoint"), "focusPoint equals position");
  // Nearer than this, the orbit's rotated position can round onto the focus
  // point and the view direction would be 0 / 0.
  if (c.focusPoint && !(glm::length(*c.focusPoint - c.position) >= schema::kSceneMinLength)) {
    fail(at.member("focusPoint"), "focusPoint is closer to position than " + formatNumber(schema::kSceneMinLength));
  }
  if (!forward) c.forward = glm::normalize(*c.focusPoint - c.position);

  // An orbit about +Y keeps the view direction's vertical component, so the
  // first frame's direction decides for every frame of the orbit.
  const glm::dvec3 used = c.orbits() ? glm::normalize(*c.focusPoint - c.position) : c.forward;
  if (std::abs(used.y) > kMaxVerticalAlignment) {
    fail(at.member(c.orbits() || !forward ? "focusPoint" : "forward"),
         "camera looks straight up or down (|dot(direction, +Y)| > 0.9999)");
  }
}

CameraSpec readCamera(od::value& v, const Location& at) {
  static constexpr std::array<std::string_view, 5> kKeys{"position", "forward", "fov", "focusPoint", "orbitVelocity"};
  CameraSpec c;
  std::optional<glm::dvec3> forward;
  const auto seen = readObject(objectOf(v, at), at, kKeys, [&](std::size_t key, od::value& m, const Location& where) {
    switch (key) {
      case 0: c.position = boundedVector(m, where); break;
      case 1: forward = boundedVector(m, where); break;
      case 2:
        c.fov = number(m, where);
        if (!(c.fov > 0.0 && c.fov < 180.0)) fail(where, "fov must lie in (0, 180) degrees");
        break;
      case 3: c.focusPoint = boundedVector(m, where); break;
      default: c.orbitVelocity = bounded(number(m, where), where);
    }
  });
  requireMembers(seen, at, kKeys, {0, 2});
  checkCamera(c, forward, at);
  return c;
}

LightData readLight(od::value& v, const Location& at) {
  static constexpr std::array<std::string_view, 3> kKeys{"directionalLightDirection", "directionalLightColor",
                                                         "ambientLightColor"};
  LightData l;
  const auto seen = readObject(objectOf(v, at), at, kKeys, [&](std::size_t key, od::value& m, const Location& where) {
    switch (key) {
      case 0: l.directionalLightDirection = glm::vec3(unitOrFail(boundedVector(m, where), where)); break;
      case 1: l.directionalLightColor = color(m, where); break;
      default: l.ambientLightColor = color(m, where);
    }
  });
  requireMembers(seen, at, kKeys, {0, 1, 2});
  return l;
}

float radius(od::value& v, const Location& at) {
  const double r = number(v, at);
  if (!(r > 0.0)) fail(at, "radius must be > 0");
  if (r < schema::kSceneMinLength || r > schema::kSceneMaxMagnitude) {
    fail(at, "radius " + formatNumber(r) + " is outside " + lengthRange());
  }
  return static_cast<float>(r);
}

Sphere readSphere(od::value& v, const Location& at) {
  static constexpr std::array<std::string_view, 3> kKeys{"position", "radius", "color"};
  Sphere s;
  const auto seen = readObject(objectOf(v, at), at, kKeys, [&](std::size_t key, od::value& m, const Location& where) {
    switch (key) {
      case 0: s.position = glm::vec3(boundedVector(m, where)); break;
      case 1: s.radius = radius(m, where); break;
      default: s.color = color(m, where);
    }
  });
  requireMembers(seen, at, kKeys, {0, 1, 2});
  return s;
}

std::vector<Sphere> readSpheres(od::value& v, const Location& at) {
  const od::json_type type = typeOf(v, at);
  if (type != od::json_type::array) fail(at, std::string("expected an array, got ") + typeName(type));
  std::vector<Sphere> spheres;
  for (auto item : take(v.get_array(), at)) {
    const Location where = at.at(spheres.size());
    od::value sphere = take(std::move(item), where);
    spheres.push_back(readSphere(sphere, where));
  }
  if (spheres.empty()) fail(at, "a scene needs at least one sphere");
  return spheres;
}

float numberInRange(od::value& v, const Location& at, double lo, double hi) {
  const double d = number(v, at);
  if (d < lo || d > hi) {
    std::ostringstream text;
    text << "must lie in [" << lo << ", " << hi << "]";
    fail(at, text.str());
  }
  return static_cast<float>(d);
}

int maxDepth(od::value& v, const Location& at) {
  const od::json_type type = typeOf(v, at);
  if (type != od::json_type::number || !take(v.is_integer(), at)) {
    fail(at, std::string("expected an integer, got ") + typeName(type));
  }
  // An integer beyond int64 (but within uint64) is as far out of range as 65.
  std::int64_t d = 0;
  if (v.get_int64().get(d) != simdjson::SUCCESS || d < 1 || d > kMaxDepthLimit) {
    fail(at, "maxDepth must lie in [1, 64]");
  }
  return static_cast<int>(d);
}

RenderParams readRender(od::value& v, const Location& at) {
  static constexpr std::array<std::string_view, 5> kKeys{"maxDepth", "reflectivity", "shininess", "specularStrength",
                                                         "background"};
  RenderParams p;
  // Ranges beyond the render model's list (chosen): a reflectivity or specular
  // strength outside [0, 1] or a negative exponent is a typo, never a look.
  readObject(objectOf(v, at), at, kKeys, [&](std::size_t key, od::value& m, const Location& where) {
    switch (key) {
      case 0: p.maxDepth = maxDepth(m, where); break;
      case 1: p.reflectivity = numberInRange(m, where, 0.0, 1.0); break;
      case 2: p.shininess = numberInRange(m, where, 0.0, 1e6); break;
      case 3: p.specularStrength = numberInRange(m, where, 0.0, 1.0); break;
      default: p.background = color(m, where);
    }
  });
  return p;
}

// The whole document, read in one forward pass (simdjson's On-Demand API).
Scene readDocument(od::document& doc) {
  static constexpr std::array<std::string_view, 4> kKeys{"camera", "lightData", "spheres", "render"};
  const Location root;
  const od::json_type type = take(doc.type(), root);
  if (type != od::json_type::object) fail(root, std::string("expected an object, got ") + typeName(type));
  Scene scene;
  const auto seen =
      readObject(take(doc.get_object(), root), root, kKeys, [&](std::size_t key, od::value& m, const Location& where) {
        switch (key) {
          case 0: scene.camera = readCamera(m, where); break;
          case 1: scene.lightData = readLight(m, where); break;
          case 2: scene.spheres = readSpheres(m, where); break;
          default: scene.render = readRender(m, where);
        }
      });
  requireMembers(seen, root, kKeys, {0, 1, 2});
  // Past the root object the document must end ("{...} {...}" is no scene).
  if (doc.current_location().error() != simdjson::OUT_OF_BOUNDS) throw SyntaxFault{"", simdjson::TRAILING_CONTENT};
  return scene;
}

std::string parseErrorMessage(std::size_t byte, const std::string& what, std::string_view text) {
  // nlohmann reports a byte offset; people want line and column.
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  const auto colon = what.rfind(": ");
  return "malformed JSON at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " +
         (colon == std::string::npos ? what : what.substr(colon + 2));
}

// nlohmann's reading of a text the fast path refused: the first syntax
// error with its line and column, or the JSON path of a number that
// overflows to infinity (nlohmann rejects it while parsing, so the path is
// tracked along the parse).
class NlohmannCheck final : public nlohmann::json_sax<Json> {
 public:
  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(false); }
  bool key(string_t& k) override {
    levels_.back().key = k;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    if (const auto* syntax = dynamic_cast<const Json::parse_error*>(&e)) {
      syntaxByte_ = syntax->byte;
      syntaxWhat_ = syntax->what();
      return false;
    }
    value();  // the failed value occupies the next array slot
    for (const Level& l : levels_) {
      if (l.array) {
        failedPath_.append("[").append(std::to_string(l.index)).append("]");
      } else {
        if (!failedPath_.empty()) failedPath_.append(".");
        failedPath_.append(l.key);
      }
    }
    return false;
  }

  // Throws what nlohmann finds wrong with `text`, if anything.
  void judge(std::string_view text, const std::string& sourceName) {
    if (Json::sax_parse(text, this)) return;
    if (syntaxByte_) throw SceneError(sourceName, "", parseErrorMessage(*syntaxByte_, syntaxWhat_, text));
    throw SceneError(sourceName, failedPath_, "not a finite number");
  }

 private:
  struct Level {
    bool array;
    long index = -1;
    std::string key;
  };
  bool value() {
    if (!levels_.empty() && levels_.back().array) ++levels_.back().index;
    return true;
  }
  bool open(bool array) {
    value();
    levels_.push_back(Level{array, -1, {}});
    return true;
  }
  bool close() {
    levels_.pop_back();
    return true;
  }
  std::vector<Level> levels_;
  std::string failedPath_;
  std::optional<std::size_t> syntaxByte_;
  std::string syntaxWhat_;
};

// Below this the hash is cheaper than starting a thread for it.
constexpr std::size_t kHashOnThreadBytes = std::size_t{1} << 20;

std::future<std::string> startHash(std::string_view text) {
  const std::span bytes(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  const auto policy = text.size() >= kHashOnThreadBytes ? std::launch::async : std::launch::deferred;
  return std::async(policy, [bytes] { return sha256Hex(bytes); });
}

// Scene text followed by simdjson::SIMDJSON_PADDING readable bytes, which
// the parser may read past the end (simdjson's On-Demand API needs them).
class PaddedText {
 public:
  explicit PaddedText(std::size_t capacity) { reserve(capacity); }
  PaddedText(std::string_view text) : PaddedText(text.size()) {
    std::memcpy(data_.get(), text.data(), text.size());
    size_ = text.size();
  }
  // Room for `capacity` bytes of text; what was read is kept.
  void reserve(std::size_t capacity) {
    auto grown = std::make_unique_for_overwrite<char[]>(capacity + simdjson::SIMDJSON_PADDING);
    if (data_) std::memcpy(grown.get(), data_.get(), size_);
    std::memset(grown.get() + capacity, 0, simdjson::SIMDJSON_PADDING);
    data_ = std::move(grown);
    capacity_ = capacity;
  }
  [[nodiscard]] char* end() { return data_.get() + size_; }
  [[nodiscard]] std::size_t room() const { return capacity_ - size_; }
  [[nodiscard]] std::size_t capacity() const { return capacity_; }
  void grow(std::size_t bytes) { size_ += bytes; }
  [[nodiscard]] std::string_view view() const { return {data_.get(), size_}; }
  [[nodiscard]] std::size_t paddedSize() const { return capacity_ + simdjson::SIMDJSON_PADDING; }

 private:
  std::unique_ptr<char[]> data_;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

// The fast path parses; any refusal is checked by nlohmann first, so a
// syntax error anywhere in the text is reported as one (with line and
// column) before any rule of the scene, as it always was.
Scene parsePadded(const PaddedText& padded, const std::string& sourceName) {
  const std::string_view text = padded.view();
  std::future<std::string> hash = startHash(text);
  try {
    od::parser parser;
    od::document doc;
    if (const auto code = parser.iterate(text.data(), text.size(), padded.paddedSize()).get(doc); code) {
      throw SyntaxFault{"", code};
    }
    Scene scene = readDocument(doc);
    scene.name = std::filesystem::path(sourceName).stem().string();
    scene.sha256 = hash.get();
    return scene;
  } catch (const Refusal& r) {
    NlohmannCheck().judge(text, sourceName);
    throw SceneError(sourceName, r.path, r.reason);
  } catch (const SyntaxFault& f) {
    NlohmannCheck().judge(text, sourceName);
    throw SceneError(sourceName, f.path, std::string("malformed JSON: ") + simdjson::error_message(f.code));
  }
}

}  // namespace

SceneError::SceneError(const std::string& file, std::string jsonPath, const std::string& reason)
    : std::runtime_error(file + ": " + (jsonPath.empty() ? std::string("(root)") : jsonPath) + ": " + reason),
      jsonPath_(std::move(jsonPath)) {}

Scene parseScene(std::string_view jsonText, const std::string& sourceName) {
  return parsePadded(PaddedText(jsonText), sourceName);
}

namespace {

// Above any scene we generate (random5000000 is 629 MB, and the loader holds
// about twice the text while parsing); a file beyond it is a mistake, not a
// scene, and is not read into memory.
constexpr std::size_t kMaxSceneFileBytes = std::size_t{1} << 30;

[[noreturn]] void failToRead(const std::filesystem::path& path, const std::string& reason) {
  throw SceneError(path.string(), "", reason + ": " + std::generic_category().message(errno));
}

SceneError tooLarge(const std::filesystem::path& path) {
  return SceneError(path.string(), "", "larger than " + std::to_string(kMaxSceneFileBytes >> 20) + " MiB");
}

// Owns an open file descriptor.
class FileHandle {
 public:
  explicit FileHandle(const std::filesystem::path& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {
    if (fd_ < 0) failToRead(path, "cannot open file");
  }
  FileHandle(const FileHandle&) = delete;
  FileHandle& operator=(const FileHandle&) = delete;
  ~FileHandle() { ::close(fd_); }
  [[nodiscard]] int fd() const { return fd_; }

 private:
  int fd_;
};

// Reads until end of file straight into the parser's padded buffer: a
// regular file's size is known up front, a pipe's buffer doubles as it fills.
PaddedText readAll(const std::filesystem::path& path, int fd, std::size_t expected) {
  PaddedText text(std::min(expected, kMaxSceneFileBytes) + 1);  // +1: end of file is seen without a regrowth
  for (;;) {
    if (text.room() == 0) text.reserve(std::min(2 * text.capacity(), kMaxSceneFileBytes + 1));
    const ssize_t got = ::read(fd, text.end(), text.room());
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) failToRead(path, "read failed");
    if (got == 0) return text;
    text.grow(static_cast<std::size_t>(got));
    if (text.view().size() > kMaxSceneFileBytes) throw tooLarge(path);
  }
}

// A regular file or a pipe (`raytracer <(generator)`); a directory or a
// device (/dev/zero would never end) is refused before reading.
PaddedText readSceneText(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec) throw SceneError(path.string(), "", "cannot open file: " + ec.message());
  if (std::filesystem::is_directory(status)) throw SceneError(path.string(), "", "is a directory, not a scene file");
  const bool regular = std::filesystem::is_regular_file(status);
  if (!regular && !std::filesystem::is_fifo(status))
    throw SceneError(path.string(), "", "not a regular file or a pipe");
  const FileHandle file(path);
  const std::size_t expected = regular ? static_cast<std::size_t>(std::filesystem::file_size(path, ec)) : 0;
  if (!ec && expected > kMaxSceneFileBytes) throw tooLarge(path);
  return readAll(path, file.fd(), ec ? 0 : std::max<std::size_t>(expected, 1 << 16));
}

}  // namespace

// The text lives only inside this call: it is gone before the renderers
// build anything from the scene.
Scene loadScene(const std::filesystem::path& path) { return parsePadded(readSceneText(path), path.string()); }

}  // namespace rt
