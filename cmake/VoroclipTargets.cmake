# Helpers shared by every module: warnings, floating-point rules, install/export.

# Flags for everything we compile. -ffp-contract=off: the predicates' error bounds assume
# every product is rounded on its own; FMA is used only where the code calls std::fma on
# purpose (two_product). Never -ffast-math.
add_library(voroclip_build_flags INTERFACE)
target_compile_options(voroclip_build_flags INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang,AppleClang>:-Wall -Wextra -Wshadow -Wconversion
    -Wnon-virtual-dtor -Wold-style-cast -ffp-contract=off -fno-math-errno>
  # Clang's -Wconversion also turns on -Wsign-conversion, which GCC's does not for C++:
  # the same warnings on both compilers (the TSan and fuzz builds use clang).
  $<$<CXX_COMPILER_ID:Clang,AppleClang>:-Wno-sign-conversion>)
if(VOROCLIP_WERROR)
  target_compile_options(voroclip_build_flags INTERFACE -Werror)
endif()
if(VOROCLIP_NATIVE)
  target_compile_options(voroclip_build_flags INTERFACE -march=native)
endif()
if(VOROCLIP_SANITIZE)
  target_compile_options(voroclip_build_flags INTERFACE
    -fsanitize=${VOROCLIP_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_link_options(voroclip_build_flags INTERFACE -fsanitize=${VOROCLIP_SANITIZE})
endif()

# voroclip_add_module(name SOURCES ... DEPENDS ... [PUBLIC_DEPS ...])
# Creates voroclip_<name> (alias voroclip::<name>) with public headers in
# <name>/include and private ones in <name>/src. DEPENDS are other voroclip modules.
function(voroclip_add_module name)
  cmake_parse_arguments(M "" "" "SOURCES;DEPENDS;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target voroclip_${name})
  if(M_SOURCES)
    add_library(${target} ${M_SOURCES})
    target_include_directories(${target}
      PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
             $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
      PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:voroclip_build_flags>)
    target_compile_features(${target} PUBLIC cxx_std_17)
    set(scope PUBLIC)
  else()
    # A module whose code has not been written yet is still a target, so that the
    # dependency chain and the installed package have their final shape.
    add_library(${target} INTERFACE)
    target_compile_features(${target} INTERFACE cxx_std_17)
    set(scope INTERFACE)
  endif()
  add_library(voroclip::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  foreach(dep IN LISTS M_DEPENDS)
    target_link_libraries(${target} ${scope} voroclip_${dep})
  endforeach()
  if(M_PUBLIC_DEPS)
    target_link_libraries(${target} ${scope} ${M_PUBLIC_DEPS})
  endif()
  if(M_PRIVATE_DEPS)
    target_link_libraries(${target} PRIVATE ${M_PRIVATE_DEPS})
  endif()
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
  install(TARGETS ${target} EXPORT voroclipTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  set_property(GLOBAL APPEND PROPERTY VOROCLIP_SHIPPED_TARGETS ${target})
endfunction()

function(voroclip_install_package)
  include(CMakePackageConfigHelpers)
  set(cfgdir ${CMAKE_INSTALL_LIBDIR}/cmake/voroclip)
  install(EXPORT voroclipTargets NAMESPACE voroclip:: DESTINATION ${cfgdir})
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/voroclipConfig.cmake.in
    ${PROJECT_BINARY_DIR}/voroclipConfig.cmake INSTALL_DESTINATION ${cfgdir})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/voroclipConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/voroclipConfig.cmake
                ${PROJECT_BINARY_DIR}/voroclipConfigVersion.cmake DESTINATION ${cfgdir})
endfunction()

# Fails the configure step when anything we ship (module libraries, the umbrella, the CLI)
# links CGAL, GMP or MPFR, directly or through another target: those are GPL/LGPL and may
# appear only in tests and optional comparison benchmarks.
function(_voroclip_collect_links target out_var)
  set(seen ${${out_var}})
  if(target IN_LIST seen)
    return()
  endif()
  list(APPEND seen ${target})
  if(TARGET ${target})
    get_target_property(aliased ${target} ALIASED_TARGET)
    if(aliased)
      _voroclip_collect_links(${aliased} seen)
    endif()
    get_target_property(type ${target} TYPE)
    set(props INTERFACE_LINK_LIBRARIES)
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      list(APPEND props LINK_LIBRARIES)
    endif()
    foreach(p IN LISTS props)
      get_target_property(libs ${target} ${p})
      if(libs)
        foreach(lib IN LISTS libs)
          string(REGEX REPLACE "^\\$<BUILD_INTERFACE:(.*)>$" "\\1" lib "${lib}")
          string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" lib "${lib}")
          _voroclip_collect_links(${lib} seen)
        endforeach()
      endif()
    endforeach()
  endif()
  set(${out_var} ${seen} PARENT_SCOPE)
endfunction()

function(voroclip_check_no_gpl_links)
  get_property(shipped GLOBAL PROPERTY VOROCLIP_SHIPPED_TARGETS)
  list(APPEND shipped voroclip)
  if(TARGET voroclip_cli)
    list(APPEND shipped voroclip_cli)
  endif()
  foreach(t IN LISTS shipped)
    set(all "")
    _voroclip_collect_links(${t} all)
    foreach(lib IN LISTS all)
      if(lib MATCHES "(^|[/:_])(CGAL|cgal|gmp|gmpxx|mpfr|GMP|MPFR)([._:]|$)|voroclip_test_gmp")
        message(FATAL_ERROR "voroclip: shipped target '${t}' links '${lib}'. CGAL, GMP and "
                            "MPFR are allowed only in tests and comparison benchmarks.")
      endif()
    endforeach()
  endforeach()
endfunction()
