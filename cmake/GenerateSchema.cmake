# Turns schema/rt_schema.json into a C++ header, so that the CSV columns,
# renderer names, algorithms, early exits and stages exist once only.
# Runs at configure time; the JSON is a configure dependency.

function(rt_json_names out json member)
  string(JSON count LENGTH "${json}" ${member})
  math(EXPR last "${count} - 1")
  set(names "")
  foreach(i RANGE ${last})
    string(JSON type TYPE "${json}" ${member} ${i})
    if(type STREQUAL "OBJECT")
      string(JSON name GET "${json}" ${member} ${i} name)
    else()
      string(JSON name GET "${json}" ${member} ${i})
    endif()
    list(APPEND names "${name}")
  endforeach()
  set(${out} "${names}" PARENT_SCOPE)
endfunction()

# enum class NAME { a, b }; plus a name table; '-' in names becomes '_'.
function(rt_enum_block out enum_name names)
  set(enumerators "")
  set(strings "")
  list(LENGTH names n)
  foreach(name IN LISTS names)
    string(REPLACE "-" "_" ident "${name}")
    # A name that is a C++ keyword gets a trailing underscore (Accel::auto_).
    if(ident STREQUAL "auto")
      set(ident "auto_")
    endif()
    string(APPEND enumerators "  ${ident},\n")
    string(APPEND strings "    \"${name}\",\n")
  endforeach()
  set(${out}
"enum class ${enum_name} : int {\n${enumerators}};\n\
inline constexpr std::array<std::string_view, ${n}> k${enum_name}Names{\n${strings}};\n\
constexpr std::string_view nameOf(${enum_name} v) { return k${enum_name}Names[static_cast<std::size_t>(v)]; }\n\n"
    PARENT_SCOPE)
endfunction()

# A C++ bit mask over `enum_name` of the names in the JSON array at the
# member path given after it ("0u | (1u << ...)").
function(rt_bit_mask out json enum_name)
  string(JSON count LENGTH "${json}" ${ARGN})
  set(mask "0u")
  if(count GREATER 0)
    math(EXPR last "${count} - 1")
    foreach(j RANGE ${last})
      string(JSON name GET "${json}" ${ARGN} ${j})
      string(APPEND mask " | (1u << static_cast<int>(${enum_name}::${name}))")
    endforeach()
  endif()
  set(${out} "${mask}" PARENT_SCOPE)
endfunction()

# One RendererDefinition initialiser for renderers[i].
function(rt_renderer_definition out json i)
  string(JSON flag GET "${json}" renderers ${i} flag)
  set(pair "")
  foreach(axis kernel scheduler)
    string(JSON type TYPE "${json}" renderers ${i} ${axis})
    if(type STREQUAL "NULL")
      string(APPEND pair " std::nullopt,")
    else()
      string(JSON value GET "${json}" renderers ${i} ${axis})
      string(SUBSTRING "${axis}" 0 1 first)
      string(TOUPPER "${first}" first)
      string(SUBSTRING "${axis}" 1 -1 rest)
      string(APPEND pair " ${first}${rest}::${value},")
    endif()
  endforeach()
  rt_bit_mask(mask "${json}" RendererOption renderers ${i} options)
  string(JSON own ERROR_VARIABLE no_own GET "${json}" renderers ${i} own_accel)
  if(no_own)
    set(own "std::nullopt")
  else()
    set(own "Accel::${own}")
  endif()
  set(${out} "    RendererDefinition{\"${flag}\",${pair} ${mask}, ${own}},\n" PARENT_SCOPE)
endfunction()

# The retired GPU variants (retired_gpu_variants): each one's name, its
# flag, the value its column reads now (the first of its 'values' list) and
# where its measurements are, as RetiredGpuVariant initialisers.
function(rt_retired_gpu_variants out json)
  string(JSON count LENGTH "${json}" retired_gpu_variants)
  math(EXPR last "${count} - 1")
  set(rows "")
  foreach(i RANGE ${last})
    foreach(field name flag values record)
      string(JSON ${field} GET "${json}" retired_gpu_variants ${i} ${field})
    endforeach()
    string(JSON kept GET "${json}" ${values} 0 name)
    string(APPEND rows "    RetiredGpuVariant{\"${name}\", \"${flag}\", \"${kept}\", \"${record}\"},\n")
  endforeach()
  set(${out} "${rows}" PARENT_SCOPE)
endfunction()

# "accel_structure" -> "AccelStructure"
function(rt_pascal_case out name)
  string(REPLACE "_" ";" parts "${name}")
  set(result "")
  foreach(part IN LISTS parts)
    string(SUBSTRING "${part}" 0 1 first)
    string(TOUPPER "${first}" first)
    string(SUBSTRING "${part}" 1 -1 rest)
    string(APPEND result "${first}${rest}")
  endforeach()
  set(${out} "${result}" PARENT_SCOPE)
endfunction()

# The keys of the metadata object at the member path given after `prefix`
# (an entry with "fields"): enum class <prefix><Name>Key and its name table,
# then the same for each of its fields that has fields of its own.
function(rt_metadata_key_blocks out json prefix)
  set(path ${ARGN})
  string(JSON name GET "${json}" ${path} name)
  rt_pascal_case(pascal "${name}")
  set(enum_name "${prefix}${pascal}")
  rt_json_names(fields "${json}" "${path};fields")
  rt_enum_block(blocks "${enum_name}Key" "${fields}")
  string(JSON count LENGTH "${json}" ${path} fields)
  math(EXPR last "${count} - 1")
  foreach(i RANGE ${last})
    string(JSON nested ERROR_VARIABLE flat GET "${json}" ${path} fields ${i} fields)
    if(NOT flat)
      rt_metadata_key_blocks(nested_blocks "${json}" "${enum_name}" ${path} fields ${i})
      string(APPEND blocks "${nested_blocks}")
    endif()
  endforeach()
  set(${out} "${blocks}" PARENT_SCOPE)
endfunction()

# The keys inside the run metadata's objects (run_metadata[].fields), in a
# header of their own: only the metadata writer needs them.
function(rt_generate_metadata_keys_header json_path header_path)
  file(READ "${json_path}" json)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${json_path}")
  string(JSON count LENGTH "${json}" run_metadata)
  math(EXPR last "${count} - 1")
  set(blocks "")
  foreach(i RANGE ${last})
    string(JSON fields ERROR_VARIABLE flat GET "${json}" run_metadata ${i} fields)
    if(NOT flat)
      rt_metadata_key_blocks(entry_blocks "${json}" Metadata run_metadata ${i})
      string(APPEND blocks "${entry_blocks}")
    endif()
  endforeach()
  set(content
"// Generated from schema/rt_schema.json by cmake/GenerateSchema.cmake. Do not edit.\n\
// The keys of each run metadata object: enum class Metadata<Object>Key (Metadata<Object><Field>Key for\n\
// an object inside one) and its names, in schema order.\n\
#pragma once\n#include <array>\n#include <cstddef>\n#include <string_view>\n\nnamespace rt::schema {\n\n\
${blocks}}  // namespace rt::schema\n")
  file(CONFIGURE OUTPUT "${header_path}" CONTENT "${content}")
endfunction()

function(rt_generate_schema_header json_path header_path)
  file(READ "${json_path}" json)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${json_path}")
  string(JSON version GET "${json}" version)

  rt_json_names(renderers "${json}" renderers)
  rt_json_names(phases "${json}" phases)
  rt_json_names(algorithms "${json}" algorithms)
  rt_json_names(early_exits "${json}" early_exits)
  rt_json_names(accels "${json}" accels)
  rt_json_names(box_paddings "${json}" box_paddings)
  rt_json_names(traversals "${json}" traversals)
  rt_json_names(gpu_bvhs "${json}" gpu_bvhs)
  rt_json_names(gpu_schedules "${json}" gpu_schedules)
  rt_json_names(gpu_paths "${json}" gpu_paths)
  rt_json_names(gpu_rt_reorders "${json}" gpu_rt_reorders)
  rt_json_names(precisions "${json}" precisions)
  rt_json_names(stages "${json}" stages)
  rt_json_names(partitions "${json}" partitions)
  rt_json_names(present_modes "${json}" present_modes)
  rt_json_names(swapchain_present_modes "${json}" swapchain_present_modes)
  rt_json_names(columns "${json}" frame_csv)
  rt_json_names(meta_keys "${json}" run_metadata)
  rt_json_names(kernels "${json}" kernels)
  rt_json_names(schedulers "${json}" schedulers)
  rt_json_names(renderer_options "${json}" renderer_options)

  rt_enum_block(b_renderers RendererKind "${renderers}")
  rt_enum_block(b_phases Phase "${phases}")
  rt_enum_block(b_algorithms Algorithm "${algorithms}")
  rt_enum_block(b_exits EarlyExit "${early_exits}")
  rt_enum_block(b_accels Accel "${accels}")
  rt_enum_block(b_box_paddings BoxPadding "${box_paddings}")
  rt_enum_block(b_traversals Traversal "${traversals}")
  rt_enum_block(b_gpu_bvhs GpuBvh "${gpu_bvhs}")
  rt_enum_block(b_gpu_schedules GpuSchedule "${gpu_schedules}")
  rt_enum_block(b_gpu_paths GpuPath "${gpu_paths}")
  rt_enum_block(b_gpu_rt_reorders GpuRtReorder "${gpu_rt_reorders}")
  rt_enum_block(b_precisions Precision "${precisions}")
  rt_enum_block(b_stages Stage "${stages}")
  rt_enum_block(b_partitions Partition "${partitions}")
  rt_enum_block(b_present PresentMode "${present_modes}")
  rt_enum_block(b_swapchain_present SwapchainPresentMode "${swapchain_present_modes}")
  rt_enum_block(b_columns FrameCsvColumn "${columns}")
  rt_enum_block(b_meta RunMetadataKey "${meta_keys}")
  rt_enum_block(b_kernels Kernel "${kernels}")
  rt_enum_block(b_schedulers Scheduler "${schedulers}")
  rt_enum_block(b_options RendererOption "${renderer_options}")

  # Renderer rows: flag, backend, the CPU renderers' (kernel, scheduler)
  # pair and the renderer options each accepts, in renderer order.
  string(JSON count LENGTH "${json}" renderers)
  math(EXPR last "${count} - 1")
  set(renderer_defs "")
  foreach(i RANGE ${last})
    rt_renderer_definition(def "${json}" ${i})
    string(APPEND renderer_defs "${def}")
  endforeach()

  set(option_flags "")
  string(JSON count LENGTH "${json}" renderer_options)
  math(EXPR last "${count} - 1")
  foreach(i RANGE ${last})
    string(JSON flag GET "${json}" renderer_options ${i} flag)
    string(APPEND option_flags "    \"${flag}\",\n")
  endforeach()
  list(LENGTH renderer_options n_options)

  string(JSON lane_widths GET "${json}" lane_widths)
  string(JSON n_lane_widths LENGTH "${json}" lane_widths)
  string(REGEX REPLACE "[][ ]" "" lane_widths "${lane_widths}")

  rt_retired_gpu_variants(retired_rows "${json}")
  string(JSON n_retired LENGTH "${json}" retired_gpu_variants)

  # The scene loader's number limits; any JSON number text is a C++ literal.
  string(JSON scene_max_magnitude GET "${json}" scene_limits max_magnitude)
  string(JSON scene_min_length GET "${json}" scene_limits min_length)

  # Stage -> algorithm and early-exit set, in stage order.
  string(JSON count LENGTH "${json}" stages)
  math(EXPR last "${count} - 1")
  set(stage_defs "")
  foreach(i RANGE ${last})
    string(JSON alg GET "${json}" stages ${i} algorithm)
    string(REPLACE "-" "_" alg "${alg}")
    rt_bit_mask(mask "${json}" EarlyExit stages ${i} early_exits)
    string(APPEND stage_defs "    StageDefinition{Algorithm::${alg}, ${mask}},\n")
  endforeach()

  list(LENGTH renderers n_renderers)
  list(LENGTH stages n_stages)
  set(content
"// Generated from schema/rt_schema.json by cmake/GenerateSchema.cmake. Do not edit.\n\
#pragma once\n#include <array>\n#include <optional>\n#include <string_view>\n\nnamespace rt::schema {\n\n\
inline constexpr int kVersion = ${version};\n\n\
${b_renderers}${b_phases}${b_algorithms}${b_exits}${b_accels}${b_box_paddings}${b_traversals}${b_gpu_bvhs}${b_gpu_schedules}${b_gpu_paths}${b_gpu_rt_reorders}${b_precisions}${b_stages}${b_partitions}${b_present}${b_swapchain_present}${b_columns}${b_meta}\
${b_kernels}${b_schedulers}${b_options}\
inline constexpr std::array<std::string_view, ${n_options}> kRendererOptionFlags{\n${option_flags}};\n\n\
// --lanes values besides 'native' (pixels per SIMD packet).\n\
inline constexpr std::array<int, ${n_lane_widths}> kLaneWidths{${lane_widths}};\n\n\
// A renderer row: its flag, whether it runs on the CPU as a (kernel,\n\
// scheduler) pair (nullopt for the GPU renderer), and the renderer options\n\
// it accepts as a bit mask over RendererOption; ownAccel: the structure a\n\
// renderer always uses, whatever --accel says (Embree's own BVH).\n\
struct RendererDefinition {\n  std::string_view flag;\n  std::optional<Kernel> kernel;\n\
  std::optional<Scheduler> scheduler;\n  unsigned optionMask;\n  std::optional<Accel> ownAccel;\n\
  [[nodiscard]] constexpr bool accepts(RendererOption o) const { return (optionMask >> static_cast<int>(o)) & 1u; }\n};\n\
inline constexpr std::array<RendererDefinition, ${n_renderers}> kRendererDefinitions{{\n${renderer_defs}}};\n\n\
struct StageDefinition {\n  Algorithm algorithm;\n  unsigned earlyExitMask;\n};\n\
inline constexpr std::array<StageDefinition, ${n_stages}> kStageDefinitions{{\n${stage_defs}}};\n\n\
// A GPU variant that was retired: its value, the flag that chose it, the\n\
// value the flag's column reads now, and where its measurements are.\n\
struct RetiredGpuVariant {\n  std::string_view name;\n  std::string_view flag;\n  std::string_view kept;\n\
  std::string_view record;\n};\n\
inline constexpr std::array<RetiredGpuVariant, ${n_retired}> kRetiredGpuVariants{{\n${retired_rows}}};\n\n\
// Numbers a scene may hold (scene_limits; docs/render-model.md section 1).\n\
inline constexpr double kSceneMaxMagnitude = ${scene_max_magnitude};\n\
inline constexpr double kSceneMinLength = ${scene_min_length};\n\n\
}  // namespace rt::schema\n")
  file(CONFIGURE OUTPUT "${header_path}" CONTENT "${content}")
endfunction()

# --- the run-time axes (schema: axes), in a header of their own: only the
# command line applies them, so a change to them rebuilds no kernel. --------

# The index of `name` in the schema list `list` (of names or named objects);
# a configure error naming `what` where it is not there.
function(rt_index_of out json list name what)
  rt_json_names(names "${json}" ${list})
  list(FIND names "${name}" index)
  if(index LESS 0)
    message(FATAL_ERROR "schema/rt_schema.json: ${what}: '${name}' is not one of ${list} (${names})")
  endif()
  set(${out} ${index} PARENT_SCOPE)
endfunction()

# A C++ bit mask over the indices of the names in the JSON array at the
# member path given after `list` (names of the schema list `list`).
function(rt_index_mask out json list what)
  string(JSON count LENGTH "${json}" ${ARGN})
  set(mask "0u")
  if(count GREATER 0)
    math(EXPR last "${count} - 1")
    foreach(j RANGE ${last})
      string(JSON name GET "${json}" ${ARGN} ${j})
      rt_index_of(index "${json}" ${list} "${name}" "${what}")
      string(APPEND mask " | (1u << ${index})")
    endforeach()
  endif()
  set(${out} "${mask}" PARENT_SCOPE)
endfunction()

# "gpu_rt_reorders" -> "GpuRtReorder": the enum generated from a value list.
function(rt_enum_of_list out list)
  string(REGEX REPLACE "s$" "" singular "${list}")
  rt_pascal_case(pascal "${singular}")
  set(${out} "${pascal}" PARENT_SCOPE)
endfunction()

# "a \"b\"" for a C++ string literal.
function(rt_cxx_string out text)
  string(REPLACE "\\" "\\\\" text "${text}")
  string(REPLACE "\"" "\\\"" text "${text}")
  set(${out} "\"${text}\"" PARENT_SCOPE)
endfunction()

# What axis `i` holds: its values (a span of a generated name table, empty
# for count and toggle), its default and its minimum.
function(rt_axis_values out_values out_default out_minimum json i)
  string(JSON name GET "${json}" axes ${i} name)
  string(JSON kind GET "${json}" axes ${i} kind)
  set(minimum 0)
  if(kind STREQUAL "choice")
    string(JSON list GET "${json}" axes ${i} values)
    string(JSON default_name GET "${json}" axes ${i} default)
    rt_index_of(default "${json}" ${list} "${default_name}" "axes ${name} default")
    rt_enum_of_list(enum "${list}")
    set(values "k${enum}Names")
  elseif(kind STREQUAL "count")
    string(JSON default GET "${json}" axes ${i} default)
    string(JSON minimum GET "${json}" axes ${i} minimum)
    set(values "{}")
  elseif(kind STREQUAL "toggle")
    string(JSON default GET "${json}" axes ${i} default)
    if(default)
      set(default 1)
    else()
      set(default 0)
    endif()
    set(values "{}")
  else()
    message(FATAL_ERROR "schema/rt_schema.json: axes ${name}: unknown kind '${kind}' (choice, count, toggle)")
  endif()
  set(${out_values} "${values}" PARENT_SCOPE)
  set(${out_default} "${default}" PARENT_SCOPE)
  set(${out_minimum} "${minimum}" PARENT_SCOPE)
endfunction()

# One AxisDefinition initialiser for axes[i].
function(rt_axis_definition out json i)
  string(JSON name GET "${json}" axes ${i} name)
  string(JSON flag GET "${json}" axes ${i} flag)
  string(JSON kind GET "${json}" axes ${i} kind)
  string(JSON description GET "${json}" axes ${i} description)
  rt_cxx_string(description "${description}")
  rt_axis_values(values default minimum "${json}" ${i})
  string(JSON renderers ERROR_VARIABLE every GET "${json}" axes ${i} renderers)
  if(every)
    string(JSON count LENGTH "${json}" renderers)
    set(mask "((1u << ${count}) - 1u)")
  else()
    rt_bit_mask(mask "${json}" RendererKind axes ${i} renderers)
  endif()
  string(JSON for_all ERROR_VARIABLE not_for_all GET "${json}" axes ${i} default_for_all)
  if(not_for_all OR NOT for_all)
    set(for_all false)
  else()
    set(for_all true)
  endif()
  set(${out}
      "    AxisDefinition{\"${flag}\", AxisKind::${kind}, ${values}, ${default}, ${minimum}, ${mask}, ${for_all},\n                   ${description}},\n"
      PARENT_SCOPE)
endfunction()

# The values (a mask over the schema list of axis `on`) that axis `on`
# must have for axes[i]; `on` must be an earlier choice axis, so that the
# CLI has set it when it checks axes[i].
function(rt_axis_requirement out json i on)
  string(JSON name GET "${json}" axes ${i} name)
  rt_json_names(axes "${json}" axes)
  list(FIND axes "${on}" on_index)
  if(on_index LESS 0 OR on_index GREATER_EQUAL i)
    message(FATAL_ERROR "schema/rt_schema.json: axes ${name}: requires '${on}', which is not an earlier axis")
  endif()
  string(JSON on_kind GET "${json}" axes ${on_index} kind)
  if(NOT on_kind STREQUAL "choice")
    message(FATAL_ERROR "schema/rt_schema.json: axes ${name}: requires '${on}', which is not a choice")
  endif()
  string(JSON list GET "${json}" axes ${on_index} values)
  rt_index_mask(mask "${json}" ${list} "axes ${name} requires ${on}" axes ${i} requires ${on})
  set(${out} "    AxisRequirement{Axis::${name}, Axis::${on}, ${mask}},\n" PARENT_SCOPE)
endfunction()

# The AxisRequirement and AxisConditionalDefault rows of axes[i].
function(rt_axis_conditions out_requirements out_defaults json i)
  string(JSON name GET "${json}" axes ${i} name)
  set(requirements "")
  string(JSON count ERROR_VARIABLE none LENGTH "${json}" axes ${i} requires)
  if(NOT none AND count GREATER 0)
    math(EXPR last "${count} - 1")
    foreach(j RANGE ${last})
      string(JSON on MEMBER "${json}" axes ${i} requires ${j})
      rt_axis_requirement(row "${json}" ${i} "${on}")
      string(APPEND requirements "${row}")
    endforeach()
  endif()
  set(defaults "")
  string(JSON count ERROR_VARIABLE none LENGTH "${json}" axes ${i} default_when)
  if(NOT none AND count GREATER 0)
    string(JSON list GET "${json}" axes ${i} values)
    rt_json_names(axes "${json}" axes)
    math(EXPR last "${count} - 1")
    foreach(j RANGE ${last})
      foreach(field axis is default)
        string(JSON ${field} GET "${json}" axes ${i} default_when ${j} ${field})
      endforeach()
      list(FIND axes "${axis}" on_index)
      string(JSON on_list GET "${json}" axes ${on_index} values)
      rt_index_of(is_index "${json}" ${on_list} "${is}" "axes ${name} default_when")
      rt_index_of(default_index "${json}" ${list} "${default}" "axes ${name} default_when")
      string(APPEND defaults "    AxisConditionalDefault{Axis::${name}, Axis::${axis}, ${is_index}, ${default_index}},\n")
    endforeach()
  endif()
  set(${out_requirements} "${requirements}" PARENT_SCOPE)
  set(${out_defaults} "${defaults}" PARENT_SCOPE)
endfunction()

# "inline constexpr std::array<Type, N> kName{{rows}};", N counted from the
# rows (each "    Type{...},", its initialiser may go on over more lines).
function(rt_table out type name rows)
  string(REGEX MATCHALL "    ${type}{" starts "${rows}")
  list(LENGTH starts n)
  set(${out} "inline constexpr std::array<${type}, ${n}> ${name}{{\n${rows}}};\n" PARENT_SCOPE)
endfunction()

function(rt_generate_axes_header json_path header_path)
  file(READ "${json_path}" json)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${json_path}")
  rt_json_names(axes "${json}" axes)
  rt_enum_block(b_axes Axis "${axes}")
  rt_enum_block(b_kinds AxisKind "choice;count;toggle")
  string(JSON count LENGTH "${json}" axes)
  math(EXPR last "${count} - 1")
  set(definitions "")
  set(requirements "")
  set(defaults "")
  foreach(i RANGE ${last})
    rt_axis_definition(row "${json}" ${i})
    string(APPEND definitions "${row}")
    rt_axis_conditions(required default_rows "${json}" ${i})
    string(APPEND requirements "${required}")
    string(APPEND defaults "${default_rows}")
  endforeach()
  rt_table(t_definitions AxisDefinition kAxisDefinitions "${definitions}")
  rt_table(t_requirements AxisRequirement kAxisRequirements "${requirements}")
  rt_table(t_defaults AxisConditionalDefault kAxisConditionalDefaults "${defaults}")
  set(content
"// Generated from schema/rt_schema.json (axes) by cmake/GenerateSchema.cmake. Do not edit.\n\
#pragma once\n#include <array>\n#include <cstddef>\n#include <span>\n#include <string_view>\n\n#include \"rt_schema.h\"\n\n\
namespace rt::schema {\n\n${b_axes}${b_kinds}\
// An axis: its option, its kind, its values (choice: the schema list's names),\n\
// its default (choice: an index into values; count: the number, below minimum\n\
// where the renderer chooses; toggle: 0 or 1), the renderers that take it as a\n\
// bit mask over RendererKind, and whether every renderer takes its default.\n\
struct AxisDefinition {\n  std::string_view flag;\n  AxisKind kind;\n  std::span<const std::string_view> values;\n\
  int defaultValue;\n  int minimum;\n  unsigned rendererMask;\n  bool defaultForAll;\n  std::string_view description;\n\
  [[nodiscard]] constexpr bool takenBy(RendererKind r) const { return (rendererMask >> static_cast<int>(r)) & 1u; }\n};\n\
${t_definitions}\n\
// Where `axis` is given, axis `on` must have one of the values in valueMask\n\
// (bits over its value indices).\n\
struct AxisRequirement {\n  Axis axis;\n  Axis on;\n  unsigned valueMask;\n};\n${t_requirements}\n\
// Where `axis` is not given and axis `on` has the value onValue, the default of\n\
// `axis` is `value` (indices into each one's values).\n\
struct AxisConditionalDefault {\n  Axis axis;\n  Axis on;\n  int onValue;\n  int value;\n};\n${t_defaults}\n\
}  // namespace rt::schema\n")
  file(CONFIGURE OUTPUT "${header_path}" CONTENT "${content}")
endfunction()
