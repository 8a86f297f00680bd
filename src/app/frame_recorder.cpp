#include "app/frame_recorder.h"

#include <charconv>
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

void appendField(std::string& out, FrameCsvColumn column, const RunIdentity& id, const FrameRecord& r) {
  switch (column) {
    case FrameCsvColumn::run_id: return appendText(out, id.runId);
    case FrameCsvColumn::scene: return appendText(out, id.scene);
    case FrameCsvColumn::renderer: return appendText(out, nameOf(id.renderer.kind));
    case FrameCsvColumn::threads: return appendText(out, std::to_string(id.renderer.threads));
    case FrameCsvColumn::lanes: return appendText(out, std::to_string(id.renderer.lanes));
    case FrameCsvColumn::simd_target: return appendText(out, id.renderer.simdTarget);
    case FrameCsvColumn::grain: return appendText(out, std::to_string(id.renderer.grain.value_or(0)));
    case FrameCsvColumn::partition:
      if (id.renderer.partition) appendText(out, nameOf(*id.renderer.partition));
      return;
    case FrameCsvColumn::algorithm: return appendText(out, nameOf(id.options.algorithm));
    case FrameCsvColumn::early_exit: return appendText(out, id.options.earlyExits.toString());
    case FrameCsvColumn::accel: return appendText(out, nameOf(id.options.accel));
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
  }
  throw std::logic_error("unhandled CSV column");
}

}  // namespace

std::string formatFrameCsv(const RunIdentity& identity, std::span<const FrameRecord> records) {
  std::string out;
  const auto& columns = schema::kFrameCsvColumnNames;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (c > 0) out += ',';
    out += columns[c];
  }
  out += '\n';
  for (const FrameRecord& r : records) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c > 0) out += ',';
      appendField(out, static_cast<FrameCsvColumn>(c), identity, r);
    }
    out += '\n';
  }
  return out;
}

}  // namespace rt
