# Fixture of the Install.* tests: installs the build tree into PREFIX (after
# removing PREFIX and the external program's build folder) and checks the
# installed layout that README.md documents:
#   <LIBDIR>/femorph/FEMorph/FEMorph.so, libFEMorphFilters.so, the plugins file
#   <LIBDIR>/femorph/femorph.plugins.xml (FEMorph, auto_load="1"),
#   <PYTHON_DESTINATION>/femorph/__init__.py and FEMorphFilters.so,
#   <LIBDIR>/cmake/femorph/FEMorphConfig.cmake and its version file,
#   and as headers exactly include/femorph/<HEADERS> and ParaView's
#   include/FEMorph_plugins.h (no private header, no core header).
#
# cmake -DBUILD_DIR=build -DPREFIX=dir -DEXTERNAL_BUILD_DIR=dir -DLIBDIR=lib
#       -DPYTHON_DESTINATION=lib/python3.11/dist-packages -DHEADERS="a.h|b.h"
#       -P install_tree.cmake
foreach (var IN ITEMS BUILD_DIR PREFIX EXTERNAL_BUILD_DIR LIBDIR HEADERS)
  if (NOT DEFINED ${var})
    message(FATAL_ERROR "install_tree.cmake: ${var} is not set")
  endif ()
endforeach ()

file(REMOVE_RECURSE "${PREFIX}" "${EXTERNAL_BUILD_DIR}")
execute_process(
  COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${PREFIX}"
  RESULT_VARIABLE result
  OUTPUT_VARIABLE output
  ERROR_VARIABLE  output)
if (NOT result EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${result}):\n${output}")
endif ()

set(expected_files
  "${LIBDIR}/femorph/FEMorph/FEMorph.so"
  "${LIBDIR}/femorph/FEMorph/libFEMorphFilters.so"
  "${LIBDIR}/femorph/femorph.plugins.xml"
  "${LIBDIR}/cmake/femorph/FEMorphConfig.cmake"
  "${LIBDIR}/cmake/femorph/FEMorphConfigVersion.cmake")
if (PYTHON_DESTINATION)
  list(APPEND expected_files
    "${PYTHON_DESTINATION}/femorph/__init__.py"
    "${PYTHON_DESTINATION}/femorph/FEMorphFilters.so")
endif ()
foreach (file IN LISTS expected_files)
  if (NOT EXISTS "${PREFIX}/${file}")
    message(FATAL_ERROR "not installed: ${PREFIX}/${file}")
  endif ()
endforeach ()

file(READ "${PREFIX}/${LIBDIR}/femorph/femorph.plugins.xml" plugins_xml)
if (NOT plugins_xml MATCHES "<Plugin name=\"FEMorph\" auto_load=\"1\"/>")
  message(FATAL_ERROR "femorph.plugins.xml does not autoload FEMorph:\n${plugins_xml}")
endif ()

string(REPLACE "|" ";" headers "${HEADERS}")
set(expected_headers "include/FEMorph_plugins.h")
foreach (header IN LISTS headers)
  list(APPEND expected_headers "include/femorph/${header}")
endforeach ()
file(GLOB_RECURSE installed_headers RELATIVE "${PREFIX}"
  "${PREFIX}/*.h" "${PREFIX}/*.hh" "${PREFIX}/*.hpp" "${PREFIX}/*.hxx" "${PREFIX}/*.txx")
list(SORT expected_headers)
list(SORT installed_headers)
if (NOT installed_headers STREQUAL expected_headers)
  message(FATAL_ERROR "installed headers:\n  ${installed_headers}\nexpected:\n  ${expected_headers}")
endif ()
list(LENGTH expected_files n_files)
list(LENGTH installed_headers n_headers)
message(STATUS "FEMorph installed into ${PREFIX}: ${n_files} files checked, ${n_headers} headers")
