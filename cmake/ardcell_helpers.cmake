# ardcell_glob_sources(VAR dir): every .cpp below dir (CONFIGURE_DEPENDS, so new files are seen).
function(ardcell_glob_sources var dir)
  file(GLOB_RECURSE found CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${dir}/*.cpp)
  set(${var} ${found} PARENT_SCOPE)
endfunction()

# ardcell_embed_cl_sources(VAR dir): generates a .cpp that holds every dir/*.cl as a string,
# reachable through kernels/cl_sources.h (cl_source(name)). Rebuilt when a .cl file changes.
function(ardcell_embed_cl_sources var dir)
  file(GLOB cl_files CONFIGURE_DEPENDS ${dir}/*.cl)
  set(out ${PROJECT_BINARY_DIR}/generated/ardcell/cl_sources_embedded.cpp)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DCL_DIR=${dir} -P
            ${PROJECT_SOURCE_DIR}/cmake/embed_cl.cmake
    DEPENDS ${cl_files} ${PROJECT_SOURCE_DIR}/cmake/embed_cl.cmake
    COMMENT "Embedding OpenCL C sources"
    VERBATIM)
  set(${var} ${out} PARENT_SCOPE)
endfunction()
