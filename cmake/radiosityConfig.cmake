# radiosityConfig.cmake - find_package(radiosity) for an installed radiosity library.
#   radiosity::radiosity         the shared library (libradiosity.so): needs nothing more
#   radiosity::radiosity_static  the static library (libradiosity.a), defined when the
#                                libraries it links (OpenMP, Embree 3, assimp, stb, OpenEXR)
#                                are found too
include("${CMAKE_CURRENT_LIST_DIR}/radiosityTargets.cmake")

find_package(OpenMP QUIET COMPONENTS C)
find_package(embree 3 QUIET)
find_package(OpenEXR 3 QUIET CONFIG)
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(ASSIMP QUIET IMPORTED_TARGET assimp)
  pkg_check_modules(STB QUIET IMPORTED_TARGET stb)
endif()
if(OpenMP_C_FOUND AND embree_FOUND AND OpenEXR_FOUND AND TARGET PkgConfig::ASSIMP
   AND TARGET PkgConfig::STB)
  include("${CMAKE_CURRENT_LIST_DIR}/radiosityStaticTargets.cmake")
endif()
