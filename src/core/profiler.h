#pragma once
// Tracy's own macros when the build has Tracy (RT_TRACY=ON defines
// TRACY_ENABLE). Otherwise the few macros this project uses expand to
// nothing, exactly as Tracy.hpp's would; this keeps a build without Tracy
// free of Tracy's sources, which come from a fetch (scripts/fetch-tracy-client).
#ifdef TRACY_ENABLE
#include <tracy/Tracy.hpp>
#else
#define ZoneScoped
#define ZoneScopedN(name)
#define ZoneValue(value)
#define FrameMark
#define TracyPlot(name, value)
#define TracyPlotConfig(name, type, step, fill, color)
#define TracyMessage(text, size)
#define TracyIsConnected false
#endif
