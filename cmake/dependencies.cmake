# Every dependency is a Debian package (scripts/install-deps.sh installs them).
find_package(embree 3 REQUIRED)
find_package(TBB REQUIRED)
# EXR and PNG read and written, JPEG read, directly (film/image_exr.cpp, image_png.cpp,
# image_jpeg.cpp): these libraries cost a process start a few milliseconds.
find_package(OpenEXR 3 REQUIRED)
find_package(PNG REQUIRED)
find_package(JPEG REQUIRED)
# Every other image format goes through OpenImageIO, linked only into the module
# steradian_oiio.so that film/image_io.cpp loads with dlopen on first use: OpenImageIO pulls in
# some 260 shared libraries (0.3 CPU-s and 130 MB at every process start when linked).
# Debian's OpenImageIO CMake config lists /usr/include/opencv4 as an include directory
# (OpenCV is an optional dependency not installed here), so we locate the library directly.
find_path(OIIO_INCLUDE_DIR OpenImageIO/imageio.h REQUIRED)
find_library(OIIO_LIBRARY OpenImageIO REQUIRED)
find_library(OIIO_UTIL_LIBRARY OpenImageIO_Util REQUIRED)
add_library(steradian_oiio INTERFACE)
target_include_directories(steradian_oiio SYSTEM INTERFACE ${OIIO_INCLUDE_DIR})
target_link_libraries(steradian_oiio INTERFACE ${OIIO_LIBRARY} ${OIIO_UTIL_LIBRARY})
# zlib: gzip-compressed scene files and PLY meshes (core/input_file.cpp).
find_package(ZLIB REQUIRED)
# NanoVDB (header-only, Debian's libnanovdb-dev): .nvdb grids of "nanovdb" media
# (media/nanovdb.cpp; zlib for ZIP-compressed grids, BLOSC ones are refused).
find_path(NANOVDB_INCLUDE_DIR nanovdb/NanoVDB.h REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json REQUIRED)
if(STERADIAN_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(STERADIAN_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
