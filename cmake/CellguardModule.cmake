# cellguard_module(<name> [INCLUDE_DIR <dir>] SOURCES <cpp...> HEADERS <hpp...>
#                  [PUBLIC_DEPS <targets...>] [PRIVATE_DEPS <targets...>])
#
# One lib/ module: a static library cellguard_<name> with an explicit source
# list (no glob), one include root whose headers are cellguard/<module>/...,
# and declared public and private dependencies, so the link (and the include
# path) enforces the layering: a module sees only the headers of the modules
# it declares. Every module is built as lib/ demands: no exceptions, no RTTI,
# no thread-safe statics, strict warnings; and the build fails when its
# objects reference the heap or the exception runtime (CheckNoHeap.cmake).
function(cellguard_module name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "INCLUDE_DIR" "SOURCES;HEADERS;PUBLIC_DEPS;PRIVATE_DEPS")
  if(NOT arg_INCLUDE_DIR)
    set(arg_INCLUDE_DIR ${CMAKE_CURRENT_SOURCE_DIR}/include)
  endif()
  set(target cellguard_${name})
  add_library(${target} STATIC ${arg_SOURCES} ${arg_HEADERS})
  add_library(cellguard::${name} ALIAS ${target})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${arg_INCLUDE_DIR}>)
  target_link_libraries(${target} PUBLIC ${arg_PUBLIC_DEPS} PRIVATE ${arg_PRIVATE_DEPS} cellguard_lib_flags)
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DLIB=$<TARGET_FILE:${target}>
            -P ${PROJECT_SOURCE_DIR}/cmake/CheckNoHeap.cmake
    COMMENT "Checking that ${target} references no heap and no exception runtime"
    VERBATIM)
endfunction()
