# Precompiled headers, a build-time measure only: what each file compiles is unchanged (the same
# headers, included first). Nearly every translation unit includes CGAL's kernel and Surface_mesh
# (through pipeline/surface_mesh.h), Eigen and nlohmann/json, and every test gtest.h; parsing them
# took ~10-20 s of each file's compile (generate_scan's 30-line main.cpp: 40 s, 7 s with the
# PCH, on a loaded machine). They are precompiled once per compile-flag variant and every target
# reuses that PCH (REUSE_FROM), instead of each target precompiling its own (most targets are one
# file, so a per-target PCH would save nothing).
#
# A PCH is only valid for files compiled with the same macros and code-generation flags, so the
# variants are: tests (gtest.h, GTEST_HAS_PTHREAD) or not, -fopenmp (defines _OPENMP, which Eigen
# tests) or not, and CGAL::Eigen3_support (CGAL_EIGEN3_ENABLED, tested by CGAL) or not. The core
# carries OpenMP and CGAL's Eigen support for every stage, so in practice there are two variants,
# tests and the rest (there were six, ~20 s of CPU each, when libraries added them one by one). Targets
# that do not link the core (no CGAL flags) get no PCH, nor do the solver and its users (solve_lib
# sets -march, whose SSE macros Eigen tests, and the solver's files use no CGAL: loading the PCH
# would cost them more than it saves).
# Configure with -DUSE_PCH=OFF to build without.

# What pipeline/surface_mesh.h and most files include. Not more: GCC maps the whole PCH into
# every compile (this one is ~500 MB; loading it costs a few s of CPU even for a file that uses
# none of it), so headers only some files use (AABB_tree, json) stay out.
set(PCH_HEADERS
  <CGAL/Exact_predicates_inexact_constructions_kernel.h>
  <CGAL/Surface_mesh.h>
  <Eigen/Core>
  <Eigen/Geometry>
  <algorithm> <array> <cmath> <cstdio> <functional> <map> <memory> <string> <vector>)

# The core's files that include none of it (command line, units, progress, atomic writes, file
# checks, the .msh reader): the PCH would make them slower.
set(PCH_SKIP_SOURCES cli.cpp units.cpp progress.cpp atomic_write.cpp require_file.cpp read_msh.cpp)

# Every build-system target under dir (recursively).
function(pch_collect_targets dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub ${subdirs})
    pch_collect_targets(${sub} sub_targets)
    list(APPEND targets ${sub_targets})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

# The libraries whose usage requirements (compile flags) reach target: its own link libraries and,
# through them, their INTERFACE_LINK_LIBRARIES (a static library's PRIVATE links appear there as
# $<LINK_ONLY:...>, which carries no compile flags, so those are not followed).
function(pch_usage_closure target out)
  get_target_property(todo ${target} LINK_LIBRARIES)
  set(seen "")
  while(todo)
    list(POP_FRONT todo lib)
    if(NOT lib OR lib MATCHES "^\\$<" OR lib IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${lib})
    if(TARGET ${lib})
      get_target_property(interface ${lib} INTERFACE_LINK_LIBRARIES)
      if(interface)
        list(APPEND todo ${interface})
      endif()
    endif()
  endwhile()
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

# The host target that precompiles the variant's header (created on first use).
function(pch_host variant is_test is_openmp is_cgal_eigen out)
  set(host pch_host_${variant})
  if(NOT TARGET ${host})
    add_library(${host} OBJECT ${CMAKE_SOURCE_DIR}/cmake/pch_host.cpp)
    # The core's usage requirements (CGAL's -frounding-math and defines, Eigen, json, the source
    # root) through the libraries the core links publicly, not through the core itself, which
    # would make the core wait for its own PCH.
    get_target_property(core_links pipeline INTERFACE_LINK_LIBRARIES)
    list(FILTER core_links EXCLUDE REGEX "^\\$<")
    get_target_property(core_includes pipeline INTERFACE_INCLUDE_DIRECTORIES)
    target_link_libraries(${host} PRIVATE ${core_links})
    target_include_directories(${host} PRIVATE ${core_includes})
    set(headers ${PCH_HEADERS})
    if(is_test)
      target_link_libraries(${host} PRIVATE GTest::gtest)
      list(APPEND headers <gtest/gtest.h>)
    endif()
    if(is_openmp)
      target_link_libraries(${host} PRIVATE OpenMP::OpenMP_CXX)
    endif()
    if(is_cgal_eigen)
      include(CGAL_Eigen3_support)  # its imported target is local to the folder that included it
      target_link_libraries(${host} PRIVATE CGAL::Eigen3_support)
    endif()
    target_precompile_headers(${host} PRIVATE ${headers})
  endif()
  set(${out} ${host} PARENT_SCOPE)
endfunction()

pch_collect_targets(${CMAKE_SOURCE_DIR} all_targets)
foreach(target ${all_targets})
  get_target_property(type ${target} TYPE)
  if(NOT type MATCHES "^(EXECUTABLE|STATIC_LIBRARY)$" OR target MATCHES "^pch_host_")
    continue()
  endif()
  get_target_property(options ${target} COMPILE_OPTIONS)
  if(options MATCHES "-march")
    continue()
  endif()
  pch_usage_closure(${target} closure)
  if((NOT "pipeline" IN_LIST closure AND NOT target STREQUAL "pipeline") OR "solve_lib" IN_LIST closure)
    continue()
  endif()
  set(is_test OFF)
  set(is_openmp OFF)
  set(variant core)
  if("GTest::gtest" IN_LIST closure)
    set(is_test ON)
    set(variant tests)
  endif()
  if("OpenMP::OpenMP_CXX" IN_LIST closure)
    set(is_openmp ON)
    string(APPEND variant _openmp)
  endif()
  set(is_cgal_eigen OFF)
  if("CGAL::Eigen3_support" IN_LIST closure)
    set(is_cgal_eigen ON)
    string(APPEND variant _cgal_eigen)
  endif()
  pch_host(${variant} ${is_test} ${is_openmp} ${is_cgal_eigen} host)
  target_precompile_headers(${target} REUSE_FROM ${host})
endforeach()
get_target_property(core_dir pipeline SOURCE_DIR)
foreach(source ${PCH_SKIP_SOURCES})
  set_source_files_properties(${core_dir}/${source} TARGET_DIRECTORY pipeline PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
endforeach()
