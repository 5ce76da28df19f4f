# Finds the Debian-packaged dependencies and fails with the package to install when one is
# missing. scripts/setup.sh installs all of them.

macro(voroclip_require_package name debian_package)
  find_package(${name} ${ARGN} QUIET)
  if(NOT ${name}_FOUND)
    message(FATAL_ERROR
      "voroclip: missing dependency ${name}. Install the Debian package '${debian_package}' "
      "(apt-get install ${debian_package}), or run scripts/setup.sh which installs everything.")
  endif()
endmacro()

voroclip_require_package(Eigen3 libeigen3-dev 3.3 NO_MODULE)
voroclip_require_package(TBB libtbb-dev CONFIG)
# JSON point files (core); header-only, needed only to build.
voroclip_require_package(nlohmann_json nlohmann-json3-dev 3.2 CONFIG)

# L-BFGS(-B) of the CVT optimiser (cvt); header-only (MIT), needed only to build.
find_path(LBFGSPP_INCLUDE_DIR LBFGSB.h)
if(NOT LBFGSPP_INCLUDE_DIR)
  message(FATAL_ERROR "voroclip: missing dependency LBFGSpp. Install the Debian package "
                      "'liblbfgspp-dev' (or run scripts/setup.sh which installs everything).")
endif()

# The apps, and the fuzz targets of the command line's density files (fuzz/fuzz_density.cpp
# compiles apps/density_options.cpp).
if(VOROCLIP_BUILD_APPS OR VOROCLIP_FUZZ)
  voroclip_require_package(CLI11 libcli11-dev CONFIG)
  # Formulas of --density / --sizing (apps/density_options.h says why muparser; MIT).
  voroclip_require_package(muparser libmuparser-dev CONFIG)
  voroclip_require_package(nlohmann_json nlohmann-json3-dev 3.2 CONFIG)
endif()

if(VOROCLIP_BUILD_TESTS)
  voroclip_require_package(Catch2 catch2 2 CONFIG)
  voroclip_require_package(nlohmann_json nlohmann-json3-dev 3.2 CONFIG)
  # GMP (C++ interface) is the exact rational oracle of the predicate tests. Tests only.
  find_path(GMPXX_INCLUDE_DIR gmpxx.h)
  find_library(GMPXX_LIBRARY gmpxx)
  find_library(GMP_LIBRARY gmp)
  if(NOT GMPXX_INCLUDE_DIR OR NOT GMPXX_LIBRARY OR NOT GMP_LIBRARY)
    message(FATAL_ERROR "voroclip: tests need GMP's C++ interface. Install the Debian "
                        "package 'libgmp-dev' (or run scripts/setup.sh).")
  endif()
  add_library(voroclip_test_gmp INTERFACE)
  target_include_directories(voroclip_test_gmp INTERFACE ${GMPXX_INCLUDE_DIR})
  target_link_libraries(voroclip_test_gmp INTERFACE ${GMPXX_LIBRARY} ${GMP_LIBRARY})
  if(VOROCLIP_WITH_CGAL_TESTS)
    voroclip_require_package(CGAL libcgal-dev CONFIG)
  endif()
endif()

if(VOROCLIP_BUILD_BENCH)
  voroclip_require_package(benchmark libbenchmark-dev CONFIG)
endif()
