# Compiler flags. The Fortran macros of include/ expand to long lines, hence no line limit
# (STYLE.md item 11). Debug is the configuration CI runs the `unit` label in (.ci/run).
set(CMAKE_Fortran_FLAGS "${CMAKE_Fortran_FLAGS} -cpp -ffree-line-length-none -fimplicit-none")
set(CMAKE_Fortran_FLAGS_RELEASE "-O2 -march=x86-64-v2 -funroll-loops")
set(CMAKE_Fortran_FLAGS_RELWITHDEBINFO "-O2 -g")
set(CMAKE_Fortran_FLAGS_DEBUG
    "-O0 -g -fcheck=all -ffpe-trap=invalid,zero,overflow -fbacktrace -Wall -Wextra -Wno-compare-reals -Wno-maybe-uninitialized")
set(CMAKE_C_STANDARD 11)
set(CMAKE_C_FLAGS_RELEASE "-O2")
set(CMAKE_C_FLAGS_DEBUG "-O0 -g -Wall -Wextra")

option(RODSOLVE_SANITIZE "Build C code with -fsanitize=address,undefined" OFF)
if(RODSOLVE_SANITIZE)
    add_compile_options($<$<COMPILE_LANGUAGE:C>:-fsanitize=address,undefined>)
    add_link_options(-fsanitize=address,undefined)
endif()
