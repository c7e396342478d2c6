# Installs the build tree into a private prefix, builds tests/consumer
# against it with find_package(ipmc_swim), and runs the example on the
# installed model. Invoked by CTest with -DSOURCE_DIR and -DBUILD_DIR.
set(work ${BUILD_DIR}/consumer_check)
file(REMOVE_RECURSE ${work})
set(prefix ${work}/prefix)

function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed: ${ARGV}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
# The installed headers are the public ones (the coupling, the model's
# fields, a body's resistance, a point's velocity); the internal headers
# (plugin/, sim/base, sim/linear) are used from the build tree only.
set(public_headers
  "ipmc_swim/fields.h;ipmc_swim/ipmc_swim.h;ipmc_swim/point_velocity.h;ipmc_swim/resistance.h")
file(GLOB_RECURSE installed_headers RELATIVE ${prefix}/include ${prefix}/include/*)
list(SORT installed_headers)
if(NOT installed_headers STREQUAL public_headers)
  message(FATAL_ERROR "installed headers: ${installed_headers} (expected ${public_headers})")
endif()
# A sanitized package needs its runtime in the consumer too.
set(consumer_flags "")
if(SANITIZE)
  set(consumer_flags "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined")
endif()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${work}/build
    -DCMAKE_PREFIX_PATH=${prefix} -DEXAMPLE_SOURCE=${SOURCE_DIR}/sim/example_attach.cc
    ${consumer_flags})
run(${CMAKE_COMMAND} --build ${work}/build)
# The public headers together, each name they declare defined in the library.
run(${work}/build/public_headers)
file(READ ${work}/build/models_dir.txt models_dir)
set(ENV{LD_LIBRARY_PATH} "${prefix}/lib:${prefix}/lib/x86_64-linux-gnu:$ENV{LD_LIBRARY_PATH}")
run(${work}/build/example_attach ${models_dir}/flagellum3.xml 2000)
message(STATUS "${last_output}")
if(NOT last_output MATCHES "qvel\\[0\\] = ")
  message(FATAL_ERROR "example_attach printed no result: ${last_output}")
endif()
# An attached mj_copyData branch goes on bit for bit (the state is in mjData).
if(NOT last_output MATCHES "branch after [0-9]+ more steps: identical")
  message(FATAL_ERROR "example_attach's branch did not continue as the original: ${last_output}")
endif()

# The installed program runs without LD_LIBRARY_PATH (its RUNPATH finds the
# libraries) and finds the installed models by default: a 0.2 s bench sine.
unset(ENV{LD_LIBRARY_PATH})
run(${prefix}/bin/ipmc-swim --version)
if(NOT last_output MATCHES "^ipmc-swim [0-9]+\\.[0-9]+\\.[0-9]+")
  message(FATAL_ERROR "ipmc-swim --version printed: ${last_output}")
endif()
run(${prefix}/bin/ipmc-swim bench --duration-s 0.2 --out ${work}/bench.csv)
if(NOT EXISTS ${prefix}/share/ipmc_swim/scenarios/paper.toml)
  message(FATAL_ERROR "scenarios not installed under share/ipmc_swim/scenarios")
endif()
message(STATUS "installed program: ${last_output}")

# The documentation is installed: README.md and every docs/*.md with the
# gallery the documents show.
set(doc_dir ${prefix}/share/doc/ipmc_swim)
file(GLOB source_docs RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/README.md ${SOURCE_DIR}/docs/*.md
     ${SOURCE_DIR}/docs/gallery/*)
foreach(doc ${source_docs})
  string(REGEX REPLACE "^docs/" "" installed_doc ${doc})
  if(NOT EXISTS ${doc_dir}/${installed_doc})
    message(FATAL_ERROR "${doc} is not installed as ${doc_dir}/${installed_doc}")
  endif()
endforeach()
