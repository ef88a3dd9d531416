# Every dependency is a Debian 12 package. A missing one stops the configuration with the name of
# the package to install, so that a new machine is one `apt-get install` away from a build.
include(FindPkgConfig)

function(silt_missing what debian_package)
  message(FATAL_ERROR "silt needs ${what}: install it with `apt-get install ${debian_package}`")
endfunction()

find_package(TBB CONFIG QUIET)
if(NOT TBB_FOUND)
  silt_missing("oneTBB" "libtbb-dev")
endif()

find_package(Eigen3 3.4 CONFIG QUIET NO_MODULE)
if(NOT Eigen3_FOUND)
  silt_missing("Eigen 3.4" "libeigen3-dev")
endif()

find_package(doctest CONFIG QUIET)
if(NOT doctest_FOUND)
  silt_missing("doctest" "doctest-dev")
endif()

find_package(CLI11 CONFIG QUIET)
if(NOT CLI11_FOUND)
  silt_missing("CLI11" "libcli11-dev")
endif()

find_package(nlohmann_json 3 CONFIG QUIET)
if(NOT nlohmann_json_FOUND)
  silt_missing("nlohmann-json" "nlohmann-json3-dev")
endif()

find_package(PNG QUIET)
if(NOT PNG_FOUND)
  silt_missing("libpng" "libpng-dev")
endif()

if(NOT PKG_CONFIG_FOUND)
  silt_missing("pkg-config" "pkg-config")
endif()
pkg_check_modules(TOMLPP QUIET IMPORTED_TARGET tomlplusplus)
if(NOT TOMLPP_FOUND)
  silt_missing("toml++" "libtomlplusplus-dev")
endif()
pkg_check_modules(OSMESA QUIET IMPORTED_TARGET osmesa)
if(NOT OSMESA_FOUND)
  silt_missing("OSMesa" "libosmesa6-dev")
endif()

pkg_check_modules(FREETYPE QUIET IMPORTED_TARGET freetype2)
if(NOT FREETYPE_FOUND)
  silt_missing("FreeType" "libfreetype-dev")
endif()
if(NOT EXISTS "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
  message(WARNING "silt draws text with DejaVu Sans: install fonts-dejavu-core (or set SILT_FONT at run time)")
endif()
find_package(Threads REQUIRED)

# CHOLMOD (SuiteSparse 5.12 on Debian 12) ships neither a CMake config nor a pkg-config file.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
if(NOT CHOLMOD_INCLUDE_DIR OR NOT CHOLMOD_LIBRARY)
  silt_missing("CHOLMOD" "libsuitesparse-dev")
endif()
add_library(silt_cholmod INTERFACE)
target_include_directories(silt_cholmod SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(silt_cholmod INTERFACE ${CHOLMOD_LIBRARY})
