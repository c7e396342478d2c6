# Fails when docs/SCENARIO_KEYS.md is not what `ipmc-swim keys --format
# markdown` prints, i.e. when the documented keys and the parser's key
# table (sim/core/scenario_keys.cc) disagree. Run by CTest as
#   cmake -DCLI=<ipmc-swim> -DDOC=<project>/docs/SCENARIO_KEYS.md -P tests/check_key_docs.cmake
execute_process(COMMAND ${CLI} keys --format markdown
  OUTPUT_VARIABLE printed RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "ipmc-swim keys --format markdown failed (${status})")
endif()
file(READ ${DOC} committed)
if(NOT printed STREQUAL committed)
  message(FATAL_ERROR "${DOC} differs from `ipmc-swim keys --format markdown`; "
    "regenerate it: build/sim/ipmc-swim keys --format markdown > docs/SCENARIO_KEYS.md")
endif()
