# Finds plumage's dependencies as Debian 12 ships them. Three of the shipped
# CMake configs are broken (see docs/building.md); these
# are the workarounds.
find_package(PkgConfig REQUIRED)

# Embree 3: its config works.
find_package(embree 3 REQUIRED)

# OpenImageIO: the exported config names files from other packages, so use pkg-config.
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)

# OpenSubdiv: the config names static libraries Debian does not ship.
find_library(OSD_CPU osdCPU REQUIRED)
find_path(OSD_INCLUDE opensubdiv/far/topologyRefiner.h REQUIRED)
add_library(plumage_opensubdiv INTERFACE)
target_link_libraries(plumage_opensubdiv INTERFACE ${OSD_CPU})
target_include_directories(plumage_opensubdiv INTERFACE ${OSD_INCLUDE})

# OpenMesh: the config works; its targets have no namespace.
find_package(OpenMesh REQUIRED)

# Assimp (glTF export, export/): its config works.
find_package(assimp REQUIRED)

pkg_check_modules(CJSON REQUIRED IMPORTED_TARGET libcjson)
pkg_check_modules(CMOCKA REQUIRED IMPORTED_TARGET cmocka)
find_package(Threads REQUIRED)

# An adapter built as a module (common/module.h): a shared object opened on
# first use, exporting nothing but its table, installed into <libdir>/plumage.
include(GNUInstallDirs)
function(plumage_module name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "SOURCES;LIBS")
  add_library(${name} MODULE ${arg_SOURCES})
  set_target_properties(${name} PROPERTIES PREFIX "" C_VISIBILITY_PRESET hidden CXX_VISIBILITY_PRESET hidden)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PRIVATE ${arg_LIBS})
  install(TARGETS ${name} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/plumage)
endfunction()

# Every plumage library is a static library built from the .c/.cpp files of
# its folder (but those named after EXCLUDE), included as "folder/header.h"
# from the repository root.
function(plumage_library name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "EXCLUDE")
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.c ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  foreach(file ${arg_EXCLUDE})
    list(REMOVE_ITEM sources ${CMAKE_CURRENT_SOURCE_DIR}/${file})
  endforeach()
  add_library(${name} STATIC ${sources})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
endfunction()
