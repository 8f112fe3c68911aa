# ASan + UBSan for the configuration the test suite uses on everything that parses outside input.
if(MOCAP_SANITIZE)
    add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
    add_link_options(-fsanitize=address,undefined)
endif()
if(MOCAP_FUZZ)
    if(NOT CMAKE_C_COMPILER_ID STREQUAL "Clang")
        message(FATAL_ERROR "MOCAP_FUZZ needs clang (libFuzzer): configure with -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++")
    endif()
    # Coverage instrumentation for all project code, so libFuzzer is guided by the decoders
    # themselves and not only by the fuzz entry points.
    add_compile_options(-fsanitize=fuzzer-no-link)
endif()
