# Warning flags shared by every target: gcc and clang both build warning-free.
add_library(cellguard_warnings INTERFACE)
target_compile_options(cellguard_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Werror -Wshadow -Wnon-virtual-dtor -Wcast-align
  -Woverloaded-virtual -Wnull-dereference -Wformat=2)
# lib/ and port/ also convert nothing silently.
add_library(cellguard_strict_warnings INTERFACE)
target_link_libraries(cellguard_strict_warnings INTERFACE cellguard_warnings)
target_compile_options(cellguard_strict_warnings INTERFACE -Wconversion -Wsign-conversion -Wold-style-cast -Wdouble-promotion)
if(CELLGUARD_COVERAGE)
  add_compile_options(--coverage -O0)
  add_link_options(--coverage)
endif()
