# Compiler settings shared by every SoftTouch target, through one interface target.
add_library(softtouch_build_options INTERFACE)
add_library(softtouch::build_options ALIAS softtouch_build_options)

target_compile_options(softtouch_build_options INTERFACE
  -Wall -Wextra -Wshadow -Wnon-virtual-dtor -Wpedantic
  # Determinism: the same inputs on the same build give byte-identical caches. Fused
  # multiply-adds change rounding depending on what the optimiser chooses, so they are off.
  -ffp-contract=off
  # GCC 12 reports false -Wrestrict errors inside std::string concatenation at -O3 (GCC PR 105651).
  $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)

# Every program and test names only the shared libraries it calls into. The modules are static libraries that
# carry all their dependencies, FFmpeg and Qt included, and without this each program (softtouch-import, spawned
# for every mesh read, above all) would load about 150 libraries at start-up instead of the 20 it uses.
target_link_options(softtouch_build_options INTERFACE -Wl,--as-needed)
# LLVM's linker where it is installed (scripts/install-deps.sh installs it): it links a sanitizer build's test
# program in a fifth of the time GNU ld takes (test_editor: 0.7 s against 3.8 s), and a build links about 90.
include(CheckLinkerFlag)
check_linker_flag(CXX -fuse-ld=lld SOFTTOUCH_HAVE_LLD)
if(SOFTTOUCH_HAVE_LLD)
  target_link_options(softtouch_build_options INTERFACE -fuse-ld=lld)
endif()

if(SOFTTOUCH_STRICT)
  target_compile_options(softtouch_build_options INTERFACE -Werror)
endif()

if(SOFTTOUCH_SANITIZE)
  target_compile_options(softtouch_build_options INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
    # -O1 with line tables only: half the compile time of -O2 -g under the sanitizers (the instrumented
    # build was most of CI's wall time) with the same file:line in every report. Placed after the build
    # type's flags, so these win.
    -O1 -g1
    # UndefinedBehaviorSanitizer's pointer checks (alignment, null, object-size, pointer-overflow, vptr)
    # are off in the targets marked with softtouch_arithmetic_ub_checks(): they double those files'
    # compile time, and there AddressSanitizer already checks every access. They stay on where bytes from
    # files are reinterpreted or Qt's objects are cast (io, render, ui, analysis, the programs).
    $<$<BOOL:$<TARGET_PROPERTY:SOFTTOUCH_ARITHMETIC_UB_CHECKS>>:-fno-sanitize=alignment,null,object-size,pointer-overflow,vptr>
    # The test drivers at -O0, still instrumented: they call into the optimised modules for the work, and
    # an instrumented driver compiles in about half the time unoptimised.
    $<$<BOOL:$<TARGET_PROPERTY:SOFTTOUCH_TEST_DRIVER>>:-O0>)
  target_link_options(softtouch_build_options INTERFACE -fsanitize=address,undefined)
endif()

# softtouch_arithmetic_ub_checks(TARGET): under the sanitizers, TARGET keeps AddressSanitizer and
# UndefinedBehaviorSanitizer's arithmetic checks (overflow, shifts, division, bool and enum values,
# unreachable code) without its pointer checks: core's numerics and the test drivers (docs/design/reliability.md,
# "What CI spends its 40 minutes on").
function(softtouch_arithmetic_ub_checks target)
  set_target_properties(${target} PROPERTIES SOFTTOUCH_ARITHMETIC_UB_CHECKS ON)
endfunction()

if(SOFTTOUCH_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang" OR NOT SOFTTOUCH_SANITIZE)
    message(FATAL_ERROR "SOFTTOUCH_FUZZ needs clang and SOFTTOUCH_SANITIZE (use the asan preset)")
  endif()
  # Coverage for libFuzzer where the targets' inputs are read (softtouch_fuzz_coverage()); the targets add
  # the fuzzer's main. Not everywhere: the sanitizer suite runs in the same build, and coverage in core's
  # numerics triples its time (docs/design/reliability.md, "What CI spends its 40 minutes on").
  target_compile_options(softtouch_build_options INTERFACE
    $<$<BOOL:$<TARGET_PROPERTY:SOFTTOUCH_FUZZ_COVERAGE>>:-fsanitize=fuzzer-no-link>)
endif()

# softtouch_fuzz_coverage(TARGET): with SOFTTOUCH_FUZZ, TARGET is compiled with libFuzzer's coverage, which
# guides the fuzz targets through its code (io's readers and the targets themselves).
function(softtouch_fuzz_coverage target)
  set_target_properties(${target} PROPERTIES SOFTTOUCH_FUZZ_COVERAGE ON)
endfunction()

# softtouch_unity(TARGET): with SOFTTOUCH_UNITY, TARGET's sources compile in batches of 8, each batch one
# translation unit, so the headers they share (Eigen, Qt, the standard library) are parsed and their
# templates instantiated once per batch instead of once per file (docs/design/reliability.md, "What CI spends its
# 40 minutes on"). For modules of several sources: each test suite is one source and stays as it is. A
# file-local name (anonymous namespace, static) must then be unique across its module.
function(softtouch_unity target)
  if(SOFTTOUCH_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
endfunction()

# softtouch_add_library(NAME [LAYERS layer...] SOURCES ...) keeps each module's CMakeLists to a few lines.
# LAYERS: the module's subsystem folders, bottom first. A file includes only headers of its own layer and of
# layers before it; every source must sit in one of them. tests/structure/test_layers checks both against the
# sources (docs/design/architecture.md, "Layers").
function(softtouch_add_library name)
  cmake_parse_arguments(ARG "" "" "LAYERS;SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  if(ARG_LAYERS)
    foreach(source IN LISTS ARG_SOURCES)
      string(REGEX MATCH "^[a-z_]+/" folder "${source}")
      string(REGEX REPLACE "/$" "" folder "${folder}")
      if(NOT folder IN_LIST ARG_LAYERS)
        message(FATAL_ERROR "${name}: ${source} is not in one of its layers (${ARG_LAYERS})")
      endif()
    endforeach()
    string(JOIN "," layers ${ARG_LAYERS})
    set_property(GLOBAL APPEND PROPERTY SOFTTOUCH_MODULE_LAYERS "${name}:${layers}")
  endif()
  add_library(${name} STATIC ${ARG_SOURCES})
  softtouch_unity(${name})
  add_library(softtouch::${name} ALIAS ${name})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE softtouch::build_options ${ARG_PRIVATE_LIBS})
endfunction()
