# Embeds presets/*.toml into ardcell_host (host/scenes/preset.h: embedded_presets()).
# Included from CMakeLists.txt after ardcell_host is defined: adds a generated .cpp to it that is
# rebuilt when a preset changes. Run in script mode (-P) it writes that .cpp (OUT, PRESET_DIR).
if(CMAKE_SCRIPT_MODE_FILE)
  file(GLOB preset_files ${PRESET_DIR}/*.toml)
  list(SORT preset_files)
  set(body "// Generated from presets/*.toml by cmake/embed_presets.cmake. Do not edit.\n")
  string(APPEND body "#include \"host/scenes/preset.h\"\n\nnamespace ardcell {\nnamespace {\n")
  set(table "")
  set(i 0)
  foreach(f ${preset_files})
    get_filename_component(name ${f} NAME)
    file(READ ${f} text)
    string(APPEND body "constexpr char kPreset${i}[] = R\"ardpreset(${text})ardpreset\";\n")
    string(APPEND table "    {\"${name}\", kPreset${i}},\n")
    math(EXPR i "${i} + 1")
  endforeach()
  string(APPEND body "constexpr EmbeddedPreset kPresets[] = {\n${table}    {nullptr, nullptr}};\n")
  string(APPEND body "}  // namespace\n\nstd::span<const EmbeddedPreset> embedded_presets() {\n")
  string(APPEND body "  return {kPresets, ${i}};\n}\n\n}  // namespace ardcell\n")
  file(WRITE ${OUT}.tmp "${body}")
  file(COPY_FILE ${OUT}.tmp ${OUT} ONLY_IF_DIFFERENT)
  file(REMOVE ${OUT}.tmp)
  return()
endif()

file(GLOB ARDCELL_PRESET_FILES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/presets/*.toml)
set(ARDCELL_PRESETS_CPP ${PROJECT_BINARY_DIR}/generated/ardcell/presets_embedded.cpp)
add_custom_command(
  OUTPUT ${ARDCELL_PRESETS_CPP}
  COMMAND ${CMAKE_COMMAND} -DOUT=${ARDCELL_PRESETS_CPP} -DPRESET_DIR=${PROJECT_SOURCE_DIR}/presets
          -P ${PROJECT_SOURCE_DIR}/cmake/embed_presets.cmake
  DEPENDS ${ARDCELL_PRESET_FILES} ${PROJECT_SOURCE_DIR}/cmake/embed_presets.cmake
  COMMENT "Embedding presets/*.toml"
  VERBATIM)
target_sources(ardcell_host PRIVATE ${ARDCELL_PRESETS_CPP})
