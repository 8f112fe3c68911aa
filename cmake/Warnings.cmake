# Warnings for all project code; MOCAP_WERROR (set by the test command) makes them fatal.
add_compile_options(-Wall -Wextra)
if(MOCAP_WERROR)
    add_compile_options(-Werror)
endif()
