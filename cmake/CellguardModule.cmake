# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
# cellguard_module(<name> [INCLUDE_DIR <dir>] SOURCES <cpp...> HEADERS <hpp...>
#                  [PUBLIC_DEPS <targets...>] [PRIVATE_DEPS <targets...>])
# (PUBLIC_DEPS and PRIVATE_DEPS: other modules, cellguard_eigen or imported
# targets; anything else must be installed too, or wrapped in $<BUILD_INTERFACE:...>)
#
# One lib/ module: a static library cellguard_<name> with an explicit source
# list (no glob), one include root whose headers are cellguard/<module>/...,
# and declared public and private dependencies, so the link (and the include
# path) enforces the layering: a module sees only the headers of the modules
# it declares. Every module is built as lib/ demands: no exceptions, no RTTI,
# no thread-safe statics, strict warnings; and the build fails when its
# objects reference the heap or the exception runtime (CheckNoHeap.cmake).
#
# Installed (cmake --install): the library into lib/, the include root's
# headers into include/, the target into the export set cellguardTargets as
# cellguard::<name> (the same name as the alias in the build tree). The flags
# lib/ is compiled with (cellguard_lib_flags: -fno-exceptions, EIGEN_NO_MALLOC,
# warnings) are linked as $<BUILD_INTERFACE:...>: they reach neither a
# consumer in the build tree nor the installed package.
include(GNUInstallDirs)
function(cellguard_module name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "INCLUDE_DIR" "SOURCES;HEADERS;PUBLIC_DEPS;PRIVATE_DEPS")
  if(NOT arg_INCLUDE_DIR)
    set(arg_INCLUDE_DIR ${CMAKE_CURRENT_SOURCE_DIR}/include)
  endif()
  set(target cellguard_${name})
  add_library(${target} STATIC ${arg_SOURCES} ${arg_HEADERS})
  add_library(cellguard::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${arg_INCLUDE_DIR}>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  # A consumer of the headers needs C++17 (the variables of the top-level
  # CMakeLists.txt do not reach an installed package's consumer).
  target_compile_features(${target} PUBLIC cxx_std_17)
  target_link_libraries(${target} PUBLIC ${arg_PUBLIC_DEPS}
                                  PRIVATE ${arg_PRIVATE_DEPS} $<BUILD_INTERFACE:cellguard_lib_flags>)
  install(TARGETS ${target} EXPORT cellguardTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${arg_INCLUDE_DIR}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
          FILES_MATCHING PATTERN "*.hpp")
  add_custom_command(TARGET ${target} POST_BUILD
    COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DLIB=$<TARGET_FILE:${target}>
            -P ${PROJECT_SOURCE_DIR}/cmake/CheckNoHeap.cmake
    COMMENT "Checking that ${target} references no heap and no exception runtime"
    VERBATIM)
endfunction()
