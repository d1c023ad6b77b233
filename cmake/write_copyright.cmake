# Writes Debian's copyright file (cmake/copyright.in) with three.js's MIT licence text taken from the three.js
# installed in web/node_modules. Run at install time, not at configure time: the project's scripts install
# three.js (npm) beside the build, so it may arrive after CMake configured, and the package must carry the
# licence of the files it actually ships.
# In: THREE_DIR, TEMPLATE, OUTPUT.
set(THREE_LICENSE " The three.js MIT licence was not installed when this package was built (scripts/install-deps.sh).")
if(EXISTS ${THREE_DIR}/LICENSE)
  file(STRINGS ${THREE_DIR}/LICENSE lines ENCODING UTF-8)
  set(THREE_LICENSE "")
  foreach(line IN LISTS lines)
    if(line STREQUAL "")
      string(APPEND THREE_LICENSE " .\n")
    else()
      string(APPEND THREE_LICENSE " ${line}\n")
    endif()
  endforeach()
  string(REGEX REPLACE "\n$" "" THREE_LICENSE "${THREE_LICENSE}")
endif()
configure_file(${TEMPLATE} ${OUTPUT} @ONLY)
