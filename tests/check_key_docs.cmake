# Fails when a generated reference is not what the program prints:
# docs/SCENARIO_KEYS.md and `ipmc-swim keys --format markdown` (the
# parser's key table, sim/core/scenario_keys.cc), or docs/OPTIONS.md and
# `ipmc-swim options --format markdown` (the commands' option tables,
# sim/io/option_table.h). Run by CTest as
#   cmake -DCLI=<ipmc-swim> -DDOC=<project>/docs/SCENARIO_KEYS.md [-DSUBCOMMAND=keys]
#         -P tests/check_key_docs.cmake
if(NOT SUBCOMMAND)
  set(SUBCOMMAND keys)
endif()
execute_process(COMMAND ${CLI} ${SUBCOMMAND} --format markdown
  OUTPUT_VARIABLE printed RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "ipmc-swim ${SUBCOMMAND} --format markdown failed (${status})")
endif()
file(READ ${DOC} committed)
if(NOT printed STREQUAL committed)
  get_filename_component(doc_name ${DOC} NAME)
  message(FATAL_ERROR "${DOC} differs from `ipmc-swim ${SUBCOMMAND} --format markdown`; "
    "regenerate it: build/sim/ipmc-swim ${SUBCOMMAND} --format markdown > docs/${doc_name}")
endif()
