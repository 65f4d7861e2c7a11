# A project outside nearcap's tree, as docs/library.md shows it, built with
# find_package(nearcap) and run.  ctest runs it twice:
#   MODE=install     Install.FindPackageConsumer: nearcap installed into a
#                    scratch prefix; also every installed header compiles,
#                    and the installed program finds its shipped data under
#                    the prefix;
#   MODE=build-tree  BuildTree.FindPackageConsumer: the build folder itself
#                    (nearcap_DIR=<build>), nothing installed.
# The consumer's CMakeLists.txt is the block of docs/library.md under
# "<!-- consumer: CMakeLists.txt -->", copied verbatim; its my_tool.cpp is
# examples/library_example.cpp (the front door, nearcap/nearcap.hpp, whose
# core the README shows), run on a shipped scene and the shipped policy.
set(work "${BUILD_DIR}/${MODE}-consumer-test")
file(REMOVE_RECURSE "${work}")
file(MAKE_DIRECTORY "${work}/src")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(rc)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

# The documented CMakeLists.txt.
file(READ "${SOURCE_DIR}/docs/library.md" page)
set(marker "<!-- consumer: CMakeLists.txt -->\n```cmake\n")
string(FIND "${page}" "${marker}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "docs/library.md has no block under <!-- consumer: CMakeLists.txt -->")
endif()
string(LENGTH "${marker}" marker_length)
math(EXPR at "${at} + ${marker_length}")
string(SUBSTRING "${page}" ${at} -1 rest)
string(FIND "${rest}" "```" end)
string(SUBSTRING "${rest}" 0 ${end} documented)
file(WRITE "${work}/src/CMakeLists.txt" "${documented}")
configure_file("${SOURCE_DIR}/examples/library_example.cpp" "${work}/src/my_tool.cpp" COPYONLY)

if(MODE STREQUAL "install")
  set(prefix "${work}/prefix")
  run("cmake --install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")
  set(find_args "-DCMAKE_PREFIX_PATH=${prefix}")
  # Installed headers are those of the exported libraries (nearcap::nearcap,
  # nearcap::raytrace): none of the build-only ones, and they compile with
  # nothing but what nearcap::nearcap brings.
  foreach(build_only render view analysis/policy_fit.hpp analysis/l_near_fit.hpp analysis/device_profile_fit.hpp)
    if(EXISTS "${prefix}/include/nearcap/${build_only}")
      message(FATAL_ERROR "include/nearcap/${build_only} is installed, but its library is not exported")
    endif()
  endforeach()
  file(GLOB_RECURSE headers RELATIVE "${prefix}/include" "${prefix}/include/nearcap/*.hpp")
  list(LENGTH headers header_count)
  if(header_count LESS 40)
    message(FATAL_ERROR "only ${header_count} headers installed: ${headers}")
  endif()
  # The mesh adapters are templates for a program that already includes
  # OpenMesh or CGAL (their headers say so).
  list(REMOVE_ITEM headers nearcap/io/openmesh_adapter.hpp nearcap/io/cgal_adapter.hpp)
  set(includes "")
  foreach(h ${headers})
    string(APPEND includes "#include \"${h}\"\n")
  endforeach()
  file(WRITE "${work}/src/installed_headers.cpp" "${includes}")
  file(APPEND "${work}/src/CMakeLists.txt"
       "add_library(installed_headers OBJECT installed_headers.cpp)\n"
       "target_link_libraries(installed_headers PRIVATE nearcap::nearcap)\n")
elseif(MODE STREQUAL "build-tree")
  set(find_args "-Dnearcap_DIR=${BUILD_DIR}")
else()
  message(FATAL_ERROR "MODE must be install or build-tree, not '${MODE}'")
endif()

run("configuring the consumer" "${CMAKE_COMMAND}" -S "${work}/src" -B "${work}/build" -G Ninja ${find_args}
    -DCMAKE_BUILD_TYPE=Release)
# find_package found this nearcap, not another one on the machine.
file(STRINGS "${work}/build/CMakeCache.txt" found REGEX "^nearcap_DIR")
if(MODE STREQUAL "install")
  set(expected_dir "${prefix}/")
else()
  set(expected_dir "${BUILD_DIR}")
endif()
string(FIND "${found}" "${expected_dir}" where)
if(where EQUAL -1)
  message(FATAL_ERROR "the consumer found another nearcap (${found}), not the one in ${expected_dir}")
endif()
run("building the consumer" "${CMAKE_COMMAND}" --build "${work}/build")
# The shipped data: under the prefix once installed, in the checkout for the build tree.
if(MODE STREQUAL "install")
  set(data "${prefix}/share/nearcap")
else()
  set(data "${SOURCE_DIR}/data")
endif()
run("the consumer" "${work}/build/my_tool" "${data}/scenes/far_grazing.json" "${data}/policy.json")
message("${out}")
if(NOT out MATCHES "zpplus-corrected: [0-9]+ wrong pixels" OR NOT out MATCHES "policy: [0-9]+ wrong pixels")
  message(FATAL_ERROR "the consumer printed no judged frame")
endif()

if(MODE STREQUAL "install")
  # A consumer of the core needs no Embree (nearcap::raytrace is then not
  # found, and one that asks for it is told why), and no CMAKE_BUILD_TYPE
  # draws CGAL's performance notice from nearcap's own lookup of CGAL.
  run("configuring the consumer without Embree" "${CMAKE_COMMAND}" -S "${work}/src" -B "${work}/build-no-embree"
      -G Ninja ${find_args} -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON)
  if(out MATCHES "CGAL performance notice")
    message(FATAL_ERROR "find_package(nearcap) printed CGAL's performance notice:\n${out}")
  endif()
  file(MAKE_DIRECTORY "${work}/raytrace")
  file(WRITE "${work}/raytrace/CMakeLists.txt"
       "cmake_minimum_required(VERSION 3.22)\nproject(wants_raytrace CXX)\n"
       "find_package(nearcap CONFIG REQUIRED COMPONENTS raytrace)\n")
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${work}/raytrace" -B "${work}/raytrace/build" -G Ninja ${find_args}
                          -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc OR NOT out MATCHES "nearcap::raytrace needs Embree 3")
    message(FATAL_ERROR "COMPONENTS raytrace without Embree: rc ${rc}, not refused naming Embree:\n${out}")
  endif()

  # The installed program's defaults point into the prefix: --policy.
  file(REAL_PATH "${prefix}" real_prefix)
  run("nearcap cracks --help" "${prefix}/bin/nearcap" cracks --help)
  string(REGEX MATCH "--policy TEXT=[^ \n]*" policy_default "${out}")
  if(NOT policy_default STREQUAL "--policy TEXT=${real_prefix}/share/nearcap/policy.json")
    message(FATAL_ERROR "the installed nearcap's default policy is not the installed one: ${policy_default}")
  endif()
  message("installed nearcap: ${policy_default}")
  # ... and the program runs on a shipped scene with it.
  run("the installed nearcap cracks --method policy" "${prefix}/bin/nearcap" cracks
      "${prefix}/share/nearcap/scenes/case_d.json" --light 0 --method policy)
  if(NOT out MATCHES "\"method\":\"policy\"")
    message(FATAL_ERROR "nearcap cracks --method policy printed no policy row:\n${out}")
  endif()
  message("installed nearcap cracks --method policy: ran on ${prefix}/share/nearcap/scenes/case_d.json")
endif()
