# The temporary directory every test runs with (TMPDIR, tests/CMakeLists.txt):
#   -DMODE=setup  empties it before the first test;
#   -DMODE=check  after the last, fails listing what the tests left in it.
# Invoked by CTest with -DDIR=<the directory>.
if(MODE STREQUAL "setup")
  file(REMOVE_RECURSE ${DIR})
  file(MAKE_DIRECTORY ${DIR})
elseif(MODE STREQUAL "check")
  file(GLOB left LIST_DIRECTORIES true RELATIVE ${DIR} ${DIR}/* ${DIR}/.*)
  if(left)
    list(SORT left)
    list(LENGTH left count)
    list(JOIN left "\n  " listed)
    message(FATAL_ERROR "the tests left ${count} entries in their temporary directory ${DIR}:\n  ${listed}")
  endif()
  message(STATUS "${DIR} is empty")
else()
  message(FATAL_ERROR "MODE must be setup or check (got '${MODE}')")
endif()
