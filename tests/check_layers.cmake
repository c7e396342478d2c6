# Fails when a source file includes a header of a layer it must not depend
# on: the folders are the layers and the dependencies run one way (see
# docs/ARCHITECTURE.md). Run by CTest as
#   cmake -DSOURCE_DIR=<project> -P tests/check_layers.cmake
# Each layer lists the layers its files may include (its own is implied).
# The two bottom layers are sim/base (numbers as text, input errors), which
# includes nothing of the project, and sim/linear (the linear-systems
# toolbox), which includes only sim/base. plugin/ and controllers/ include
# these two and nothing else of sim/ (they are libraries of their own that
# a program other than ipmc-swim may link); controllers/ includes nothing
# of plugin/. Outside plugin/ no file (the program, its benchmarks and
# tests) includes a plugin header but the public ones (plugin/include,
# included as ipmc_swim/...): what the program does to a model, a user's
# program can do.
set(layers
  sim/base
  sim/linear
  sim/io
  controllers
  plugin/include
  plugin/mjcf
  plugin/fluid
  plugin/dynamics
  plugin/actuators
  plugin
  plugin/tests
  sim/core
  sim/runs
  sim/identify
  sim/batch
  renders
  sim/optimize
  sim/cli
  sim/python
  sim)
set(allowed_sim/base "")
set(allowed_sim/linear sim/base)
set(allowed_sim/io sim/base)
set(allowed_controllers sim/linear sim/base)
set(allowed_plugin/include "")
set(allowed_plugin/mjcf plugin/include sim/base)
set(allowed_plugin/fluid plugin/include plugin/mjcf sim/base)
set(allowed_plugin/dynamics plugin/include plugin/fluid plugin/mjcf sim/base)
set(allowed_plugin/actuators plugin/include plugin/mjcf sim/linear sim/base)
set(allowed_plugin plugin/include plugin/mjcf plugin/fluid plugin/dynamics plugin/actuators
  sim/linear sim/base)
# The plugin's unit tests of its internals.
set(allowed_plugin/tests plugin/include plugin/mjcf plugin/fluid plugin/dynamics plugin/actuators
  plugin sim/linear sim/base)
set(below_sim sim/base sim/linear sim/io controllers plugin/include)
set(allowed_sim/core ${below_sim})
set(allowed_sim/runs sim/core ${below_sim})
set(allowed_sim/identify sim/runs sim/core ${below_sim})
set(allowed_sim/batch sim/identify sim/runs sim/core ${below_sim})
set(allowed_renders sim/runs sim/core ${below_sim})
set(allowed_sim/optimize renders sim/batch sim/identify sim/runs sim/core ${below_sim})
set(allowed_sim/cli sim/optimize renders sim/batch sim/identify sim/runs sim/core ${below_sim})
set(allowed_sim/python sim/optimize renders sim/batch sim/identify sim/runs sim/core ${below_sim})
set(allowed_sim plugin/include)

# The layer of a path relative to the project: its longest listed prefix.
function(layer_of path out)
  set(best "")
  foreach(layer ${layers})
    string(LENGTH "${layer}" n)
    string(SUBSTRING "${path}" 0 ${n} head)
    string(LENGTH "${best}" best_n)
    if(head STREQUAL layer AND n GREATER best_n)
      string(SUBSTRING "${path}/" ${n} 1 next)
      if(next STREQUAL "/")
        set(best "${layer}")
      endif()
    endif()
  endforeach()
  set(${out} "${best}" PARENT_SCOPE)
endfunction()

set(violations "")
set(checked 0)
foreach(top plugin controllers sim renders)
  file(GLOB_RECURSE sources RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/${top}/*.h ${SOURCE_DIR}/${top}/*.cc)
  foreach(source ${sources})
    get_filename_component(dir ${source} DIRECTORY)
    layer_of("${dir}" from)
    if(from STREQUAL "")
      list(APPEND violations "${source}: its folder is not a listed layer")
      continue()
    endif()
    file(STRINGS ${SOURCE_DIR}/${source} lines REGEX "^#include \"")
    foreach(line ${lines})
      string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" header "${line}")
      if(header MATCHES "^ipmc_swim/")
        set(to plugin/include)
      else()
        get_filename_component(header_dir ${header} DIRECTORY)
        layer_of("${header_dir}" to)
      endif()
      math(EXPR checked "${checked} + 1")
      if(to STREQUAL "" OR to STREQUAL from)
        continue()
      endif()
      list(FIND allowed_${from} ${to} found)
      if(found EQUAL -1)
        list(APPEND violations "${source}: includes ${header} (layer ${to}), which ${from} must not depend on")
      endif()
    endforeach()
  endforeach()
endforeach()

# The benchmarks and tests: the public plugin headers only.
foreach(top bench tests)
  file(GLOB_RECURSE sources RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/${top}/*.h ${SOURCE_DIR}/${top}/*.cc)
  foreach(source ${sources})
    file(STRINGS ${SOURCE_DIR}/${source} lines REGEX "^#include \"plugin/")
    foreach(line ${lines})
      math(EXPR checked "${checked} + 1")
      list(APPEND violations "${source}: ${line} (outside plugin/ only the public ipmc_swim/ headers)")
    endforeach()
  endforeach()
endforeach()

if(violations)
  list(JOIN violations "\n  " text)
  message(FATAL_ERROR "layering: includes that cross a layer the wrong way:\n  ${text}")
endif()
message(STATUS "layering: ${checked} includes checked, none crosses a layer the wrong way")
