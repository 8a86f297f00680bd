#include "app/frame_recorder.h"

#include <charconv>
#include <optional>
#include <stdexcept>

#include "app/run_identity.h"

namespace rt {
namespace {

using schema::FrameCsvColumn;

// Shortest text that reads back as the same double: full precision, no rounding.
void appendNumber(std::string& out, double value) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (ec != std::errc()) throw std::runtime_error("cannot format number");
  out.append(buffer, end);
}

void appendText(std::string& out, std::string_view text) {
  if (text.find_first_of(",\"\n\r") == std::string_view::npos) {
    out += text;
    return;
  }
  out += '"';
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

void appendCount(std::string& out, std::uint64_t n) { out += std::to_string(n); }

// rays_per_depth: depth 0 (primary rays) first, up to the deepest depth that traced a ray.
void appendRaysPerDepth(std::string& out, const LaneCounters& c) {
  for (int depth = 0; depth < c.deepestDepth(); ++depth) {
    if (depth > 0) out += '/';
    appendCount(out, c.raysPerDepth[static_cast<std::size_t>(depth)]);
  }
}

// A counter column's field; empty without counters.
void appendCounterField(std::string& out, FrameCsvColumn column, const FrameCounters& counters) {
  if (!counters) return;
  const LaneCounters& c = *counters;
  switch (column) {
    case FrameCsvColumn::rays: return appendCount(out, c.rays());
    case FrameCsvColumn::rays_per_depth: return appendRaysPerDepth(out, c);
    case FrameCsvColumn::node_visits: return appendCount(out, c.nodeVisits);
    case FrameCsvColumn::node_lane_slots: return appendCount(out, c.nodeLaneSlots);
    case FrameCsvColumn::node_lanes_active: return appendCount(out, c.nodeLanesActive);
    case FrameCsvColumn::sphere_tests: return appendCount(out, c.sphereTests);
    case FrameCsvColumn::sphere_lane_slots: return appendCount(out, c.sphereLaneSlots);
    case FrameCsvColumn::sphere_lanes_active: return appendCount(out, c.sphereLanesActive);
    case FrameCsvColumn::shade_lane_slots: return appendCount(out, c.shadeLaneSlots);
    case FrameCsvColumn::shade_lanes_active: return appendCount(out, c.shadeLanesActive);
    default: throw std::logic_error("not a counter column");
  }
}

// An axis the renderer has (its schema name), or an empty field where it has none.
template <typename Axis>
void appendNameIfAny(std::string& out, const std::optional<Axis>& axis) {
  if (axis) appendText(out, nameOf(*axis));
}

void appendField(std::string& out, FrameCsvColumn column, const RunIdentity& id, const FrameRecord& r,
                 const FrameCounters& counters) {
  switch (column) {
    case FrameCsvColumn::run_id: return appendText(out, id.runId);
    case FrameCsvColumn::scene: return appendText(out, id.scene);
    case FrameCsvColumn::renderer: return appendText(out, nameOf(id.renderer.kind));
    case FrameCsvColumn::threads: return appendText(out, std::to_string(id.renderer.threads));
    case FrameCsvColumn::lanes: return appendText(out, std::to_string(id.renderer.lanes));
    case FrameCsvColumn::simd_target: return appendText(out, id.renderer.simdTarget);
    case FrameCsvColumn::grain: return appendText(out, std::to_string(id.renderer.grain.value_or(0)));
    case FrameCsvColumn::partition: return appendNameIfAny(out, id.renderer.partition);
    case FrameCsvColumn::algorithm: return appendText(out, nameOf(id.options.algorithm));
    case FrameCsvColumn::early_exit: return appendText(out, id.options.earlyExits.toString());
    case FrameCsvColumn::accel: return appendText(out, nameOf(id.options.accel));
    case FrameCsvColumn::traversal: return appendNameIfAny(out, id.renderer.traversal);
    case FrameCsvColumn::hybrid_threshold:
      if (id.renderer.hybridThreshold) appendText(out, std::to_string(*id.renderer.hybridThreshold));
      return;
    case FrameCsvColumn::gpu_bvh: return appendNameIfAny(out, id.renderer.gpuBvh);
    case FrameCsvColumn::gpu_schedule: return appendNameIfAny(out, id.renderer.gpuSchedule);
    case FrameCsvColumn::gpu_path: return appendNameIfAny(out, id.renderer.gpuPath);
    case FrameCsvColumn::gpu_rt_reorder: return appendNameIfAny(out, id.renderer.gpuRtReorder);
    case FrameCsvColumn::precision: return appendText(out, nameOf(id.renderer.precision));
    case FrameCsvColumn::width: return appendText(out, std::to_string(id.extent.width));
    case FrameCsvColumn::height: return appendText(out, std::to_string(id.extent.height));
    case FrameCsvColumn::present: return appendText(out, nameOf(id.present));
    case FrameCsvColumn::device: return appendText(out, id.device ? id.device->name : "");
    case FrameCsvColumn::frame: return appendText(out, std::to_string(r.frame));
    case FrameCsvColumn::warmup: return appendText(out, r.warmup ? "1" : "0");
    case FrameCsvColumn::update_ms: return appendNumber(out, r.updateMs);
    case FrameCsvColumn::render_ms: return appendNumber(out, r.renderMs);
    case FrameCsvColumn::present_ms: return appendNumber(out, r.presentMs);
    case FrameCsvColumn::gpu_ms:
      if (r.gpuMs) appendNumber(out, *r.gpuMs);
      return;
    case FrameCsvColumn::acquire_ms:
      if (r.acquireMs) appendNumber(out, *r.acquireMs);
      return;
    case FrameCsvColumn::rays:
    case FrameCsvColumn::rays_per_depth:
    case FrameCsvColumn::node_visits:
    case FrameCsvColumn::node_lane_slots:
    case FrameCsvColumn::node_lanes_active:
    case FrameCsvColumn::sphere_tests:
    case FrameCsvColumn::sphere_lane_slots:
    case FrameCsvColumn::sphere_lanes_active:
    case FrameCsvColumn::shade_lane_slots:
    case FrameCsvColumn::shade_lanes_active: return appendCounterField(out, column, counters);
  }
  throw std::logic_error("unhandled CSV column");
}

}  // namespace

std::string formatFrameCsv(const RunIdentity& identity, std::span<const FrameRecord> records,
                           std::span<const FrameCounters> counters) {
  if (!counters.empty() && counters.size() != records.size()) {
    throw std::logic_error("formatFrameCsv: counters are not one per record");
  }
  const FrameCounters none;
  std::string out;
  const auto& columns = schema::kFrameCsvColumnNames;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (c > 0) out += ',';
    out += columns[c];
  }
  out += '\n';
  for (std::size_t i = 0; i < records.size(); ++i) {
    const FrameCounters& frameCounters = counters.empty() ? none : counters[i];
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c > 0) out += ',';
      appendField(out, static_cast<FrameCsvColumn>(c), identity, records[i], frameCounters);
    }
    out += '\n';
  }
  return out;
}

std::optional<LaneCounters> measuredCounterTotals(std::span<const FrameRecord> records,
                                                  std::span<const FrameCounters> counters) {
  std::optional<LaneCounters> total;
  for (std::size_t i = 0; i < counters.size() && i < records.size(); ++i) {
    if (records[i].warmup || !counters[i]) continue;
    if (!total) total.emplace();
    *total += *counters[i];
  }
  return total;
}

}  // namespace rt
