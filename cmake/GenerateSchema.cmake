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
    string(APPEND enumerators "  ${ident},\n")
    string(APPEND strings "    \"${name}\",\n")
  endforeach()
  set(${out}
"enum class ${enum_name} : int {\n${enumerators}};\n\
inline constexpr std::array<std::string_view, ${n}> k${enum_name}Names{\n${strings}};\n\n"
    PARENT_SCOPE)
endfunction()

function(rt_generate_schema_header json_path header_path)
  file(READ "${json_path}" json)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${json_path}")
  string(JSON version GET "${json}" version)

  rt_json_names(renderers "${json}" renderers)
  rt_json_names(phases "${json}" phases)
  rt_json_names(algorithms "${json}" algorithms)
  rt_json_names(early_exits "${json}" early_exits)
  rt_json_names(stages "${json}" stages)
  rt_json_names(partitions "${json}" partitions)
  rt_json_names(present_modes "${json}" present_modes)
  rt_json_names(columns "${json}" frame_csv)
  rt_json_names(meta_keys "${json}" run_metadata)

  rt_enum_block(b_renderers RendererKind "${renderers}")
  rt_enum_block(b_phases Phase "${phases}")
  rt_enum_block(b_algorithms Algorithm "${algorithms}")
  rt_enum_block(b_exits EarlyExit "${early_exits}")
  rt_enum_block(b_stages Stage "${stages}")
  rt_enum_block(b_partitions Partition "${partitions}")
  rt_enum_block(b_present PresentMode "${present_modes}")
  rt_enum_block(b_columns FrameCsvColumn "${columns}")
  rt_enum_block(b_meta RunMetadataKey "${meta_keys}")

  # Renderer command-line flags, in renderer order.
  string(JSON count LENGTH "${json}" renderers)
  math(EXPR last "${count} - 1")
  set(flags "")
  foreach(i RANGE ${last})
    string(JSON flag GET "${json}" renderers ${i} flag)
    string(APPEND flags "    \"${flag}\",\n")
  endforeach()

  # Stage -> algorithm and early-exit set, in stage order.
  string(JSON count LENGTH "${json}" stages)
  math(EXPR last "${count} - 1")
  set(stage_defs "")
  foreach(i RANGE ${last})
    string(JSON alg GET "${json}" stages ${i} algorithm)
    string(REPLACE "-" "_" alg "${alg}")
    string(JSON nexits LENGTH "${json}" stages ${i} early_exits)
    set(mask "0u")
    if(nexits GREATER 0)
      math(EXPR elast "${nexits} - 1")
      foreach(j RANGE ${elast})
        string(JSON e GET "${json}" stages ${i} early_exits ${j})
        string(APPEND mask " | (1u << static_cast<int>(EarlyExit::${e}))")
      endforeach()
    endif()
    string(APPEND stage_defs "    StageDefinition{Algorithm::${alg}, ${mask}},\n")
  endforeach()

  list(LENGTH renderers n_renderers)
  list(LENGTH stages n_stages)
  set(content
"// Generated from schema/rt_schema.json by cmake/GenerateSchema.cmake. Do not edit.\n\
#pragma once\n#include <array>\n#include <string_view>\n\nnamespace rt::schema {\n\n\
inline constexpr int kVersion = ${version};\n\n\
${b_renderers}${b_phases}${b_algorithms}${b_exits}${b_stages}${b_partitions}${b_present}${b_columns}${b_meta}\
inline constexpr std::array<std::string_view, ${n_renderers}> kRendererFlags{\n${flags}};\n\n\
struct StageDefinition {\n  Algorithm algorithm;\n  unsigned earlyExitMask;\n};\n\
inline constexpr std::array<StageDefinition, ${n_stages}> kStageDefinitions{{\n${stage_defs}}};\n\n\
}  // namespace rt::schema\n")
  file(CONFIGURE OUTPUT "${header_path}" CONTENT "${content}")
endfunction()
