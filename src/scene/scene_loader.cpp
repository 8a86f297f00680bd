#include "scene/scene_loader.h"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "core/sha256.h"
#include "rt_schema.h"

namespace rt {
namespace {

using Json = nlohmann::json;

// |dot(direction, +Y)| above this means the camera looks straight up or down
// and its right vector would be undefined (docs/render-model.md section 1).
constexpr double kMaxVerticalAlignment = 0.9999;

std::string describeType(const Json& value) { return value.type_name(); }

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

// Reads one JSON object, tracking the JSON path for error messages and
// rejecting keys that nobody read (a typo must not be ignored silently).
class ObjectReader {
 public:
  ObjectReader(const Json& value, std::string path, const std::string& file)
      : value_(value), path_(std::move(path)), file_(file) {
    if (!value_.is_object()) fail(path_, "expected an object, got " + describeType(value_));
  }

  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    throw SceneError(file_, path, reason);
  }

  std::string pathOf(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  }

  const Json* find(std::string_view key) {
    known_.emplace_back(key);
    const auto it = value_.find(key);
    return it == value_.end() ? nullptr : &*it;
  }

  const Json& require(std::string_view key) {
    const Json* v = find(key);
    if (v == nullptr) fail(pathOf(key), "missing required field");
    return *v;
  }

  double number(const Json& v, const std::string& path) const {
    if (!v.is_number()) fail(path, "expected a number, got " + describeType(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path, "not a finite number");
    return d;
  }

  double number(std::string_view key) { return number(require(key), pathOf(key)); }

  std::optional<double> optionalNumber(std::string_view key) {
    const Json* v = find(key);
    if (v == nullptr) return std::nullopt;
    return number(*v, pathOf(key));
  }

  glm::dvec3 vector(const Json& v, const std::string& path) const {
    if (!v.is_array() || v.size() != 3) fail(path, "expected an array of 3 numbers");
    return {number(v[0], path + "[0]"), number(v[1], path + "[1]"), number(v[2], path + "[2]")};
  }

  glm::dvec3 vector(std::string_view key) { return vector(require(key), pathOf(key)); }

  // A number whose magnitude is at most kSceneMaxMagnitude.
  double bounded(double value, const std::string& path) const {
    if (std::abs(value) > schema::kSceneMaxMagnitude)
      fail(path, formatNumber(value) + " is outside " + magnitudeRange());
    return value;
  }

  // A position or direction: every component bounded.
  glm::dvec3 boundedVector(const Json& v, const std::string& path) const {
    const glm::dvec3 u = vector(v, path);
    for (int i = 0; i < 3; ++i) bounded(u[i], path + "[" + std::to_string(i) + "]");
    return u;
  }

  glm::dvec3 boundedVector(std::string_view key) { return boundedVector(require(key), pathOf(key)); }

  std::optional<glm::dvec3> optionalBoundedVector(std::string_view key) {
    const Json* v = find(key);
    if (v == nullptr) return std::nullopt;
    return boundedVector(*v, pathOf(key));
  }

  glm::vec3 color(const Json& v, const std::string& path) const {
    const glm::dvec3 c = vector(v, path);
    for (int i = 0; i < 3; ++i) {
      if (c[i] < 0.0 || c[i] > 1.0) fail(path + "[" + std::to_string(i) + "]", "color component outside [0, 1]");
    }
    return glm::vec3(c);
  }

  glm::vec3 color(std::string_view key) { return color(require(key), pathOf(key)); }

  void rejectUnknownKeys() const {
    for (const auto& [key, unused] : value_.items()) {
      bool known = false;
      for (const auto& k : known_) known = known || k == key;
      if (!known) fail(pathOf(key), "unknown key");
    }
  }

  const std::string& path() const { return path_; }

 private:
  const Json& value_;
  std::string path_;
  const std::string& file_;
  std::vector<std::string> known_;
};

// A direction normalised; one shorter than kSceneMinLength has no reliable
// direction (its squares underflow), so it is refused like a zero one.
glm::dvec3 unitOrFail(const ObjectReader& r, glm::dvec3 v, const std::string& path) {
  const double length = glm::length(v);
  if (length == 0.0) r.fail(path, "zero-length direction");
  if (!(length >= schema::kSceneMinLength)) {
    r.fail(path,
           "direction of length " + formatNumber(length) + " is shorter than " + formatNumber(schema::kSceneMinLength));
  }
  return v / length;
}

CameraSpec readCamera(ObjectReader r) {
  CameraSpec c;
  c.position = r.boundedVector("position");
  const auto forward = r.optionalBoundedVector("forward");
  c.fov = r.number("fov");
  if (!(c.fov > 0.0 && c.fov < 180.0)) r.fail(r.pathOf("fov"), "fov must lie in (0, 180) degrees");
  c.focusPoint = r.optionalBoundedVector("focusPoint");
  c.orbitVelocity = r.bounded(r.optionalNumber("orbitVelocity").value_or(0.0), r.pathOf("orbitVelocity"));
  r.rejectUnknownKeys();

  if (forward) c.forward = unitOrFail(r, *forward, r.pathOf("forward"));
  if (!forward && !c.focusPoint) r.fail(r.pathOf("forward"), "missing: give forward or focusPoint");
  if (c.orbits() && !c.focusPoint) {
    r.fail(r.pathOf("orbitVelocity"), "a non-zero orbitVelocity needs a focusPoint");
  }
  if (c.focusPoint && *c.focusPoint == c.position) {
    r.fail(r.pathOf("focusPoint"), "focusPoint equals position");
  }
  // Nearer than this, the orbit's rotated position can round onto the focus
  // point and the view direction would be 0 / 0.
  if (c.focusPoint && !(glm::length(*c.focusPoint - c.position) >= schema::kSceneMinLength)) {
    r.fail(r.pathOf("focusPoint"), "focusPoint is closer to position than " + formatNumber(schema::kSceneMinLength));
  }
  if (!forward) c.forward = glm::normalize(*c.focusPoint - c.position);

  // An orbit about +Y keeps the view direction's vertical component, so the
  // first frame's direction decides for every frame of the orbit.
  const glm::dvec3 used = c.orbits() ? glm::normalize(*c.focusPoint - c.position) : c.forward;
  if (std::abs(used.y) > kMaxVerticalAlignment) {
    r.fail(r.pathOf(c.orbits() || !forward ? "focusPoint" : "forward"),
           "camera looks straight up or down (|dot(direction, +Y)| > 0.9999)");
  }
  return c;
}

LightData readLight(ObjectReader r) {
  LightData l;
  l.directionalLightDirection =
      glm::vec3(unitOrFail(r, r.boundedVector("directionalLightDirection"), r.pathOf("directionalLightDirection")));
  l.directionalLightColor = r.color("directionalLightColor");
  l.ambientLightColor = r.color("ambientLightColor");
  r.rejectUnknownKeys();
  return l;
}

Sphere readSphere(ObjectReader r) {
  Sphere s;
  s.position = glm::vec3(r.boundedVector("position"));
  const double radius = r.number("radius");
  if (!(radius > 0.0)) r.fail(r.pathOf("radius"), "radius must be > 0");
  if (radius < schema::kSceneMinLength || radius > schema::kSceneMaxMagnitude) {
    r.fail(r.pathOf("radius"), "radius " + formatNumber(radius) + " is outside " + lengthRange());
  }
  s.radius = static_cast<float>(radius);
  s.color = r.color("color");
  r.rejectUnknownKeys();
  return s;
}

float numberInRange(ObjectReader& r, std::string_view key, float fallback, double lo, double hi) {
  const auto v = r.optionalNumber(key);
  if (!v) return fallback;
  if (*v < lo || *v > hi) {
    std::ostringstream range;
    range << "must lie in [" << lo << ", " << hi << "]";
    r.fail(r.pathOf(key), range.str());
  }
  return static_cast<float>(*v);
}

RenderParams readRender(ObjectReader r) {
  RenderParams p;
  if (const Json* depth = r.find("maxDepth")) {
    if (!depth->is_number_integer()) r.fail(r.pathOf("maxDepth"), "expected an integer, got " + describeType(*depth));
    const auto d = depth->get<long long>();
    if (d < 1 || d > kMaxDepthLimit) r.fail(r.pathOf("maxDepth"), "maxDepth must lie in [1, 64]");
    p.maxDepth = static_cast<int>(d);
  }
  // Ranges beyond the render model's list (chosen): a reflectivity or specular
  // strength outside [0, 1] or a negative exponent is a typo, never a look.
  p.reflectivity = numberInRange(r, "reflectivity", p.reflectivity, 0.0, 1.0);
  p.shininess = numberInRange(r, "shininess", p.shininess, 0.0, 1e6);
  p.specularStrength = numberInRange(r, "specularStrength", p.specularStrength, 0.0, 1.0);
  if (const Json* bg = r.find("background")) p.background = r.color(*bg, r.pathOf("background"));
  r.rejectUnknownKeys();
  return p;
}

std::string parseErrorMessage(const nlohmann::json::parse_error& e, std::string_view text) {
  // nlohmann reports a byte offset; people want line and column.
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  std::string what = e.what();
  const auto colon = what.rfind(": ");
  return "malformed JSON at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " +
         (colon == std::string::npos ? what : what.substr(colon + 2));
}

// Finds the JSON path of the value the parser failed on. nlohmann rejects a
// number that overflows to infinity while parsing, before any DOM exists,
// so the path has to be tracked along the parse.
class FailurePathTracker final : public nlohmann::json_sax<Json> {
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
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
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
  [[nodiscard]] const std::string& failedPath() const { return failedPath_; }

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
};

}  // namespace

SceneError::SceneError(const std::string& file, std::string jsonPath, const std::string& reason)
    : std::runtime_error(file + ": " + (jsonPath.empty() ? std::string("(root)") : jsonPath) + ": " + reason),
      jsonPath_(std::move(jsonPath)) {}

Scene parseScene(std::string_view jsonText, const std::string& sourceName) {
  Json root;
  try {
    root = Json::parse(jsonText);
  } catch (const nlohmann::json::parse_error& e) {
    throw SceneError(sourceName, "", parseErrorMessage(e, jsonText));
  } catch (const nlohmann::json::out_of_range&) {
    FailurePathTracker tracker;
    Json::sax_parse(jsonText, &tracker);
    throw SceneError(sourceName, tracker.failedPath(), "not a finite number");
  }
  ObjectReader r(root, "", sourceName);
  Scene scene;
  scene.name = std::filesystem::path(sourceName).stem().string();
  scene.sha256 = sha256Hex({reinterpret_cast<const std::uint8_t*>(jsonText.data()), jsonText.size()});
  scene.camera = readCamera(ObjectReader(r.require("camera"), "camera", sourceName));
  scene.lightData = readLight(ObjectReader(r.require("lightData"), "lightData", sourceName));

  const Json& spheres = r.require("spheres");
  if (!spheres.is_array()) r.fail("spheres", "expected an array, got " + describeType(spheres));
  if (spheres.empty()) r.fail("spheres", "a scene needs at least one sphere");
  scene.spheres.reserve(spheres.size());
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    scene.spheres.push_back(readSphere(ObjectReader(spheres[i], "spheres[" + std::to_string(i) + "]", sourceName)));
  }
  if (const Json* render = r.find("render")) scene.render = readRender(ObjectReader(*render, "render", sourceName));
  r.rejectUnknownKeys();
  return scene;
}

namespace {

// Far above any scene we generate (random1000000 is about 100 MB); a file
// beyond it is a mistake, not a scene, and is not read into memory.
constexpr std::size_t kMaxSceneFileBytes = std::size_t{512} << 20;

// A regular file or a pipe (`raytracer <(generator)`); a directory or a
// device (/dev/zero would never end) is refused before reading.
std::string readSceneText(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec) throw SceneError(path.string(), "", "cannot open file: " + ec.message());
  if (std::filesystem::is_directory(status)) throw SceneError(path.string(), "", "is a directory, not a scene file");
  if (!std::filesystem::is_regular_file(status) && !std::filesystem::is_fifo(status)) {
    throw SceneError(path.string(), "", "not a regular file or a pipe");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path.string(), "", "cannot open file: " + std::generic_category().message(errno));
  std::string text;
  std::array<char, 1 << 16> chunk{};
  while (in.read(chunk.data(), chunk.size()) || in.gcount() > 0) {
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxSceneFileBytes) {
      throw SceneError(path.string(), "", "larger than " + std::to_string(kMaxSceneFileBytes >> 20) + " MiB");
    }
  }
  if (in.bad()) throw SceneError(path.string(), "", "read failed: " + std::generic_category().message(errno));
  return text;
}

}  // namespace

Scene loadScene(const std::filesystem::path& path) { return parseScene(readSceneText(path), path.string()); }

}  // namespace rt
