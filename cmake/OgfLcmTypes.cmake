# Generates C++ headers and a Java jar from .lcm files with Debian's lcm-gen 1.3.1, which ships no CMake
# helpers (upstream's lcm_wrap_types arrived in 1.4). Everything is generated into the build tree at build
# time; nothing generated is committed.
#
#   ogf_lcm_types(TARGET ogf_lcmtypes JAR lcmtypes_ogf JAR_DIR <dir> FILES a.lcm b.lcm ...)
#
# defines an INTERFACE library TARGET (include directory with <package>/<type>.hpp, linked to lcm::lcm)
# and, when Java is available, a jar named JAR in JAR_DIR holding one class per type.

find_program(LCM_GEN_EXECUTABLE lcm-gen REQUIRED)
find_path(LCM_INCLUDE_DIR lcm/lcm-cpp.hpp REQUIRED)
# find_library rather than pkg-config: lcm.pc requires glib's .pc files that liblcm-dev does not pull in.
find_library(LCM_LIBRARY lcm REQUIRED)
if(NOT TARGET lcm::lcm)
  add_library(lcm::lcm UNKNOWN IMPORTED)
  set_target_properties(lcm::lcm PROPERTIES IMPORTED_LOCATION "${LCM_LIBRARY}"
                                            INTERFACE_INCLUDE_DIRECTORIES "${LCM_INCLUDE_DIR}")
endif()

function(ogf_lcm_types)
  cmake_parse_arguments(ARG "" "TARGET;JAR;JAR_DIR" "FILES" ${ARGN})
  set(cpp_dir "${CMAKE_CURRENT_BINARY_DIR}/lcmgen/cpp")
  set(java_dir "${CMAKE_CURRENT_BINARY_DIR}/lcmgen/java")
  set(all_hpp "")
  set(all_java "")
  foreach(lcm_file IN LISTS ARG_FILES)
    get_filename_component(abs "${lcm_file}" ABSOLUTE)
    # file(READ), not file(STRINGS): the ';' in "package x;" would split a CMake list.
    file(READ "${abs}" text)
    string(REGEX REPLACE "//[^\n]*" "" text "${text}")
    string(REGEX REPLACE "/\\*([^*]|\\*[^/])*\\*/" "" text "${text}")
    string(REGEX MATCH "package[ \t\r\n]+([A-Za-z0-9_.]+)" _ "${text}")
    set(pkg "${CMAKE_MATCH_1}")
    if(pkg STREQUAL "")
      message(FATAL_ERROR "${lcm_file}: no package line")
    endif()
    string(REPLACE "." "/" pkg_dir "${pkg}")
    string(REGEX MATCHALL "struct[ \t\r\n]+[A-Za-z0-9_]+" structs "${text}")
    set(outs "")
    foreach(s IN LISTS structs)
      string(REGEX REPLACE "struct[ \t\r\n]+" "" name "${s}")
      list(APPEND outs "${cpp_dir}/${pkg_dir}/${name}.hpp" "${java_dir}/${pkg_dir}/${name}.java")
      list(APPEND all_hpp "${cpp_dir}/${pkg_dir}/${name}.hpp")
      list(APPEND all_java "${java_dir}/${pkg_dir}/${name}.java")
    endforeach()
    add_custom_command(
      OUTPUT ${outs}
      COMMAND "${LCM_GEN_EXECUTABLE}" --cpp --cpp-std c++11 --cpp-hpath "${cpp_dir}"
              --java --jpath "${java_dir}" "${abs}"
      DEPENDS "${abs}"
      COMMENT "lcm-gen ${lcm_file}"
      VERBATIM)
  endforeach()

  add_custom_target(${ARG_TARGET}_gen DEPENDS ${all_hpp} ${all_java})
  add_library(${ARG_TARGET} INTERFACE)
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_gen)
  # Generated code is third-party style: include it as a system directory so -Werror does not trip on it.
  target_include_directories(${ARG_TARGET} SYSTEM INTERFACE "$<BUILD_INTERFACE:${cpp_dir}>")
  target_link_libraries(${ARG_TARGET} INTERFACE lcm::lcm)

  if(ARG_JAR)
    find_package(Java COMPONENTS Development)
    find_file(LCM_JAR lcm.jar PATHS /usr/share/java /usr/local/share/java NO_DEFAULT_PATH)
    if(Java_FOUND AND LCM_JAR)
      include(UseJava)
      add_jar(${ARG_JAR} SOURCES ${all_java} INCLUDE_JARS "${LCM_JAR}" OUTPUT_NAME ${ARG_JAR}
              OUTPUT_DIR "${ARG_JAR_DIR}")
      add_dependencies(${ARG_JAR} ${ARG_TARGET}_gen)
      set_property(GLOBAL PROPERTY OGF_LCM_JAR_FILE "${ARG_JAR_DIR}/${ARG_JAR}.jar")
    else()
      message(WARNING "No JDK or no lcm.jar: ${ARG_JAR}.jar (types for lcm-spy) will not be built")
    endif()
  endif()
endfunction()
