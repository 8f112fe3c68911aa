# Test helpers: every test goes through these so that sub-builds can label and filter them.
#   MOCAP_TEST_LABEL   extra label on every test of this build ("cross", "sanitize")
#   MOCAP_PARSERS_ONLY register (and build by default) only tests labelled "parser"
option(MOCAP_PARSERS_ONLY "Only build and register tests labelled 'parser' (sanitizer sub-build)" OFF)
set(MOCAP_TEST_LABEL "" CACHE STRING "Extra ctest label for every test of this build")

# Test frameworks: cmocka for C (also in cross builds), GoogleTest for C++.
find_library(CMOCKA_LIBRARY cmocka REQUIRED)
find_path(CMOCKA_INCLUDE_DIR cmocka.h REQUIRED)
add_library(mocap::cmocka UNKNOWN IMPORTED GLOBAL)
set_target_properties(mocap::cmocka PROPERTIES
    IMPORTED_LOCATION ${CMOCKA_LIBRARY}
    INTERFACE_INCLUDE_DIRECTORIES ${CMOCKA_INCLUDE_DIR})
if(NOT MOCAP_FIRMWARE_ONLY)
    find_package(GTest REQUIRED GLOBAL)
endif()

# Sub-build tests join the native ctest run, so their names carry the sub-build's label
# ("cross.test_wire") to stay unique: ctest applies test properties by name.
function(_mocap_test_name out name)
    if(MOCAP_TEST_LABEL)
        set(${out} ${MOCAP_TEST_LABEL}.${name} PARENT_SCOPE)
    else()
        set(${out} ${name} PARENT_SCOPE)
    endif()
endfunction()

function(_mocap_register_test name labels)
    set(all_labels ${labels})
    if(MOCAP_TEST_LABEL)
        list(APPEND all_labels ${MOCAP_TEST_LABEL})
    endif()
    set_tests_properties(${name} PROPERTIES LABELS "${all_labels}")
endfunction()

# _mocap_test_wanted(<out-var> <labels>): false when a parsers-only build skips the test.
function(_mocap_test_wanted out labels)
    if(MOCAP_PARSERS_ONLY AND NOT "parser" IN_LIST labels)
        set(${out} FALSE PARENT_SCOPE)
    else()
        set(${out} TRUE PARENT_SCOPE)
    endif()
endfunction()

# _mocap_add_test_program(name framework_libs base_label SOURCES ... [LIBS ...] [ARGS ...] [LABELS ...])
function(_mocap_add_test_program name framework_libs base_label)
    cmake_parse_arguments(T "" "" "SOURCES;LIBS;ARGS;LABELS" ${ARGN})
    _mocap_test_wanted(wanted "${T_LABELS}")
    if(NOT wanted)
        return()
    endif()
    add_executable(${name} ${T_SOURCES})
    target_link_libraries(${name} PRIVATE ${T_LIBS} ${framework_libs})
    set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
    _mocap_test_name(test_name ${name})
    add_test(NAME ${test_name} COMMAND ${name} ${T_ARGS})
    _mocap_register_test(${test_name} "${base_label};${T_LABELS}")
    # Scratch files go to a directory of this test in this build tree (GoogleTest's TempDir()
    # reads TEST_TMPDIR): a sub-build's copy of a test, or another checkout's, running at the
    # same time never shares them.
    set(scratch ${CMAKE_BINARY_DIR}/test-tmp/${name})
    file(MAKE_DIRECTORY ${scratch})
    set_tests_properties(${test_name} PROPERTIES ENVIRONMENT "TEST_TMPDIR=${scratch}")
endfunction()

# mocap_add_cmocka_test(name SOURCES ... [LIBS ...] [ARGS ...] [LABELS ...])
function(mocap_add_cmocka_test name)
    _mocap_add_test_program(${name} mocap::cmocka firmware ${ARGN})
endfunction()

# mocap_count_allocations(name): the test program's malloc, calloc and realloc go through
# counting wrappers (libs/testing/alloc_counting.h), for tests that check a loop allocates
# nothing. A no-op where the test is not built (parsers-only builds).
function(mocap_count_allocations name)
    if(NOT TARGET ${name})
        return()
    endif()
    target_sources(${name} PRIVATE ${PROJECT_SOURCE_DIR}/libs/testing/alloc_counting.c)
    target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/libs)
    target_link_options(${name} PRIVATE -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc)
endfunction()

# mocap_add_gtest(name SOURCES ... [LIBS ...] [ARGS ...] [LABELS ...])
function(mocap_add_gtest name)
    _mocap_add_test_program(${name} "GTest::gtest;GTest::gtest_main" hub ${ARGN})
endfunction()

# mocap_add_fuzzer(name SOURCES ... LIBS ... CORPUS dir): a libFuzzer target (MOCAP_FUZZ builds)
# whose test replays the committed corpus once, then fuzzes for a fixed, seeded number of runs.
function(mocap_add_fuzzer name)
    cmake_parse_arguments(T "" "CORPUS;RUNS" "SOURCES;LIBS" ${ARGN})
    if(NOT MOCAP_FUZZ)
        return()
    endif()
    if(NOT T_RUNS)
        set(T_RUNS 20000)
    endif()
    add_executable(${name} ${T_SOURCES})
    target_compile_options(${name} PRIVATE -fsanitize=fuzzer)
    target_link_libraries(${name} PRIVATE ${T_LIBS})
    target_link_options(${name} PRIVATE -fsanitize=fuzzer)
    set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/fuzz)
    _mocap_test_name(test_name ${name})
    add_test(NAME ${test_name}_corpus COMMAND ${name} -runs=0 ${T_CORPUS})
    _mocap_register_test(${test_name}_corpus "fuzz;parser")
    # A fixed seed and run count keep the run reproducible; the fresh-input corpus goes to a
    # scratch directory so the committed one stays as reviewed.
    add_test(NAME ${test_name}_seeded COMMAND ${name} -seed=1 -runs=${T_RUNS} -max_len=4096
        ${CMAKE_BINARY_DIR}/fuzz/${name}_scratch ${T_CORPUS})
    file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/fuzz/${name}_scratch)
    _mocap_register_test(${test_name}_seeded "fuzz;parser")
endfunction()
