#pragma once
// The run-time axes of the schema (schema: axes) as fields of RenderOptions:
// the one place that says which field holds which axis. The command line
// applies every axis through it (app/cli.cpp), generically.
#include <span>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <utility>

#include "render/render_options.h"
#include "rt_schema_axes.h"

namespace rt {

using schema::Axis;
using schema::AxisDefinition;
using schema::AxisKind;

constexpr const AxisDefinition& definitionOf(Axis axis) {
  return schema::kAxisDefinitions[static_cast<std::size_t>(axis)];
}

namespace detail {

// How to read and write one axis' field, its value as an int (a choice's
// index into its values, a count, a toggle's 0 or 1), and whether the
// field's type fits the axis' declaration.
struct AxisField {
  int (*get)(const RenderOptions&);
  void (*set)(RenderOptions&, int);
  bool (*fits)(const AxisDefinition&);
};

// A choice is an enum of the schema list it names (the same names in the
// same order), a count an int, a toggle a bool.
template <typename Value>
constexpr bool fieldFits(const AxisDefinition& d) {
  if constexpr (std::is_enum_v<Value>) {
    if (d.kind != AxisKind::choice) return false;
    for (std::size_t i = 0; i < d.values.size(); ++i) {
      if (nameOf(static_cast<Value>(i)) != d.values[i]) return false;
    }
    return true;
  } else if constexpr (std::is_same_v<Value, bool>) {
    return d.kind == AxisKind::toggle;
  } else {
    return d.kind == AxisKind::count && std::is_same_v<Value, int>;
  }
}

template <auto Field>
constexpr AxisField fieldOf() {
  using Value = std::remove_cvref_t<decltype(std::declval<RenderOptions&>().*Field)>;
  return {[](const RenderOptions& o) { return static_cast<int>(o.*Field); },
          [](RenderOptions& o, int value) { o.*Field = static_cast<Value>(value); }, fieldFits<Value>};
}

// A new axis of the schema fails to compile below (kAxisFields) until it has a field here.
constexpr AxisField fieldFor(Axis axis) {
  switch (axis) {
    case Axis::accel: return fieldOf<&RenderOptions::accel>();
    case Axis::traversal: return fieldOf<&RenderOptions::traversal>();
    case Axis::hybrid_threshold: return fieldOf<&RenderOptions::hybridThreshold>();
    case Axis::gpu_bvh: return fieldOf<&RenderOptions::gpuBvh>();
    case Axis::gpu_rt_reorder: return fieldOf<&RenderOptions::gpuRtReorder>();
    case Axis::counters: return fieldOf<&RenderOptions::counters>();
    case Axis::precision: return fieldOf<&RenderOptions::precision>();
  }
  throw std::logic_error("an axis of the schema has no RenderOptions field");
}

inline constexpr auto kAxisFields = [] {
  std::array<AxisField, schema::kAxisNames.size()> fields{};
  for (std::size_t i = 0; i < fields.size(); ++i) fields[i] = fieldFor(static_cast<Axis>(i));
  return fields;
}();

// Each field fits its declaration, and RenderOptions' defaults are the schema's.
consteval bool fieldsFollowTheSchema() {
  for (std::size_t i = 0; i < kAxisFields.size(); ++i) {
    const auto& d = schema::kAxisDefinitions[i];
    if (!kAxisFields[i].fits(d) || kAxisFields[i].get(RenderOptions{}) != d.defaultValue) return false;
  }
  return true;
}
static_assert(fieldsFollowTheSchema(),
              "RenderOptions' axis fields differ from the schema's axes (type, values or default)");

}  // namespace detail

// An axis' value in `options` as an int: a choice's index into its values, a count, a toggle's 0 or 1.
constexpr int axisValue(const RenderOptions& options, Axis axis) {
  return detail::kAxisFields[static_cast<std::size_t>(axis)].get(options);
}

constexpr void setAxisValue(RenderOptions& options, Axis axis, int value) {
  detail::kAxisFields[static_cast<std::size_t>(axis)].set(options, value);
}

}  // namespace rt
