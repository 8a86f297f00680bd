// Every run-time axis of the schema (schema/rt_schema.json, axes) goes
// through the command line's one generic path: each is accepted, with each
// of its values, by the renderers the schema gives it where what it
// requires holds, and lands in its RenderOptions field; it is refused by
// every other renderer and where a requirement does not hold. The cases are
// made from the declarations, not listed by hand, so an axis or a value the
// schema gains is covered at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <initializer_list>
#include <string>
#include <variant>
#include <vector>

#include "app/cli.h"
#include "app/render_axes.h"

namespace rt {
namespace {

using Args = std::vector<std::string>;

std::variant<RunConfig, CliExit> parseArgs(const Args& args) {
  std::vector<const char*> argv{"raytracer"};
  for (const auto& a : args) argv.push_back(a.c_str());
  return parseCommandLine(static_cast<int>(argv.size()), argv.data());
}

std::vector<RendererKind> everyRenderer() {
  std::vector<RendererKind> kinds;
  for (std::size_t i = 0; i < schema::kRendererDefinitions.size(); ++i) kinds.push_back(static_cast<RendererKind>(i));
  return kinds;
}

std::string flagOf(RendererKind kind) { return std::string(definitionOf(kind).flag); }
std::string flagOf(Axis axis) { return std::string(definitionOf(axis).flag); }

// The values to try: every choice, a count's minimum and one above, a toggle on.
std::vector<int> valuesOf(Axis axis) {
  const auto& d = definitionOf(axis);
  if (d.kind == AxisKind::count) return {d.minimum, d.minimum + 1};
  if (d.kind == AxisKind::toggle) return {1};
  std::vector<int> values;
  for (std::size_t i = 0; i < d.values.size(); ++i) values.push_back(static_cast<int>(i));
  return values;
}

// The axis with a value on a command line: "--traversal single", "--counters".
Args givenArgs(Axis axis, int value) {
  const auto& d = definitionOf(axis);
  if (d.kind == AxisKind::toggle) return {flagOf(axis)};
  if (d.kind == AxisKind::count) return {flagOf(axis), std::to_string(value)};
  return {flagOf(axis), std::string(d.values[static_cast<std::size_t>(value)])};
}

int firstValueIn(unsigned mask) {
  int value = 0;
  while (((mask >> value) & 1u) == 0) ++value;
  return value;
}

// What makes an axis applicable: each axis it requires at the first value it
// allows, and what that one requires in turn (--accel bvh --traversal hybrid).
Args satisfying(Axis axis) {
  Args args;
  for (const auto& r : schema::kAxisRequirements) {
    if (r.axis != axis) continue;
    const Args earlier = satisfying(r.on);
    args.insert(args.end(), earlier.begin(), earlier.end());
    const Args on = givenArgs(r.on, firstValueIn(r.valueMask));
    args.insert(args.end(), on.begin(), on.end());
  }
  return args;
}

Args join(std::initializer_list<Args> parts) {
  Args args;
  for (const auto& p : parts) args.insert(args.end(), p.begin(), p.end());
  return args;
}

std::string text(const Args& args) {
  std::string joined;
  for (const auto& a : args) joined += (joined.empty() ? "" : " ") + a;
  return joined;
}

// A renderer that always uses its own structure (schema own_accel) has no
// other accel: --accel with another value is refused, whatever the axis says.
bool ownAccelDiffers(RendererKind kind, Axis axis, int value) {
  const auto own = definitionOf(kind).ownAccel;
  return axis == Axis::accel && own && value != static_cast<int>(*own);
}

TEST(CliAxes, EveryValueOfEveryAxisReachesRenderOptionsForTheRenderersThatTakeIt) {
  int cases = 0;
  for (std::size_t i = 0; i < schema::kAxisDefinitions.size(); ++i) {
    const auto axis = static_cast<Axis>(i);
    for (const RendererKind kind : everyRenderer()) {
      if (!definitionOf(axis).takenBy(kind)) continue;
      for (const int value : valuesOf(axis)) {
        const Args args = join({{flagOf(kind)}, satisfying(axis), givenArgs(axis, value)});
        const auto result = parseArgs(args);
        if (ownAccelDiffers(kind, axis, value)) {
          EXPECT_TRUE(std::holds_alternative<CliExit>(result)) << text(args);
          continue;
        }
        const auto* config = std::get_if<RunConfig>(&result);
        ASSERT_NE(config, nullptr) << text(args) << ": " << std::get<CliExit>(result).error;
        EXPECT_EQ(axisValue(config->options, axis), value) << text(args);
        ++cases;
      }
    }
  }
  EXPECT_GT(cases, static_cast<int>(schema::kAxisDefinitions.size())) << "every axis has a renderer that takes it";
}

// Refused, the axis' default value too (unless every renderer has the
// default: default_for_all), naming the option, the renderer and the
// renderers that take it.
TEST(CliAxes, EveryAxisIsRefusedByTheRenderersThatDoNotTakeIt) {
  for (std::size_t i = 0; i < schema::kAxisDefinitions.size(); ++i) {
    const auto axis = static_cast<Axis>(i);
    const auto& d = definitionOf(axis);
    for (const RendererKind kind : everyRenderer()) {
      if (d.takenBy(kind)) continue;
      // A value the option parses: not the default where every renderer has it, not below a count's minimum.
      const int value = d.defaultForAll ? (d.defaultValue == 0 ? 1 : 0) : std::max(d.defaultValue, d.minimum);
      const Args args = join({{flagOf(kind)}, givenArgs(axis, value)});
      const auto result = parseArgs(args);
      const auto* refused = std::get_if<CliExit>(&result);
      ASSERT_NE(refused, nullptr) << text(args) << " was accepted";
      EXPECT_EQ(refused->code, kExitBadInput) << text(args);
      EXPECT_NE(refused->error.find(flagOf(axis) + ": renderer " + std::string(nameOf(kind)) + " does not take"),
                std::string::npos)
          << refused->error;
      for (const RendererKind taker : everyRenderer()) {
        if (d.takenBy(taker)) {
          EXPECT_NE(refused->error.find(flagOf(taker)), std::string::npos) << refused->error;
        }
      }
      if (d.defaultForAll) {
        EXPECT_TRUE(
            std::holds_alternative<RunConfig>(parseArgs(join({{flagOf(kind)}, givenArgs(axis, d.defaultValue)}))))
            << "every renderer takes the default of " << flagOf(axis);
      }
    }
  }
}

// Where an axis it requires has another value, an axis is refused, saying
// what it needs; its renderers take it otherwise (the test above).
TEST(CliAxes, EveryRequirementIsRefusedWhereItDoesNotHold) {
  ASSERT_FALSE(schema::kAxisRequirements.empty());
  for (const auto& r : schema::kAxisRequirements) {
    for (const RendererKind kind : everyRenderer()) {
      if (!definitionOf(r.axis).takenBy(kind)) continue;
      for (const int other : valuesOf(r.on)) {
        if (((r.valueMask >> other) & 1u) != 0 || ownAccelDiffers(kind, r.on, other)) continue;
        const Args args = join(
            {{flagOf(kind)}, satisfying(r.on), givenArgs(r.on, other), givenArgs(r.axis, valuesOf(r.axis).front())});
        const auto result = parseArgs(args);
        const auto* refused = std::get_if<CliExit>(&result);
        ASSERT_NE(refused, nullptr) << text(args) << " was accepted";
        EXPECT_EQ(refused->code, kExitBadInput) << text(args);
        EXPECT_NE(refused->error.find(flagOf(r.axis) + ": " + flagOf(r.axis)), std::string::npos) << refused->error;
        EXPECT_NE(refused->error.find(" needs " + flagOf(r.on) + " "), std::string::npos) << refused->error;
      }
    }
  }
}

// Not given, an axis has its default (the schema's, which RenderOptions
// shares: render_axes.h), or the one another axis' value sets where the
// renderer takes it (default_when), or the renderer's own structure.
TEST(CliAxes, AnAxisNotGivenHasItsDefault) {
  for (const RendererKind kind : everyRenderer()) {
    const auto result = parseArgs({flagOf(kind)});
    ASSERT_TRUE(std::holds_alternative<RunConfig>(result)) << flagOf(kind);
    for (std::size_t i = 0; i < schema::kAxisDefinitions.size(); ++i) {
      const auto axis = static_cast<Axis>(i);
      const auto own = definitionOf(kind).ownAccel;
      const int expected =
          axis == Axis::accel && own ? static_cast<int>(*own) : schema::kAxisDefinitions[i].defaultValue;
      EXPECT_EQ(axisValue(std::get<RunConfig>(result).options, axis), expected) << flagOf(kind) << " " << flagOf(axis);
    }
  }
  for (const auto& c : schema::kAxisConditionalDefaults) {
    for (const RendererKind kind : everyRenderer()) {
      if (ownAccelDiffers(kind, c.on, c.onValue)) continue;
      const Args args = join({{flagOf(kind)}, satisfying(c.on), givenArgs(c.on, c.onValue)});
      const auto result = parseArgs(args);
      ASSERT_TRUE(std::holds_alternative<RunConfig>(result)) << text(args);
      const int expected = definitionOf(c.axis).takenBy(kind) ? c.value : definitionOf(c.axis).defaultValue;
      EXPECT_EQ(axisValue(std::get<RunConfig>(result).options, c.axis), expected) << text(args);
    }
  }
}

}  // namespace
}  // namespace rt
