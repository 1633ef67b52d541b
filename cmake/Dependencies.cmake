# Every dependency comes from a Debian package (scripts/install-deps.sh installs them).
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)

find_package(glfw3 3.3 REQUIRED)
find_package(glm REQUIRED)
find_package(OpenEXR 3 REQUIRED)
find_package(TinyGLTF REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(GTest REQUIRED)
find_package(benchmark REQUIRED)
find_package(embree 3 REQUIRED)
find_package(TBB REQUIRED)
find_package(meshoptimizer REQUIRED)

pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)
pkg_check_modules(OSMESA REQUIRED IMPORTED_TARGET osmesa)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)

# Dear ImGui: Debian ships the core as a library and the backends as sources to compile.
set(IMGUI_BACKEND_DIR /usr/share/doc/libimgui-dev/examples/backends CACHE PATH "Dear ImGui backend sources")
if(NOT EXISTS ${IMGUI_BACKEND_DIR}/imgui_impl_opengl3.cpp)
  message(FATAL_ERROR "Dear ImGui backend sources not found in ${IMGUI_BACKEND_DIR} (install libimgui-dev)")
endif()

# OpenGL loader: glad 2 (python3-glad) generates it into the build tree from its packaged specs.
find_program(GLAD_EXECUTABLE glad REQUIRED)
set(GLAD_OUT ${CMAKE_BINARY_DIR}/glad)
add_custom_command(
  OUTPUT ${GLAD_OUT}/src/gl.c ${GLAD_OUT}/include/glad/gl.h
  COMMAND ${GLAD_EXECUTABLE} --quiet --reproducible --api gl:core=4.5
          --extensions GL_KHR_debug,GL_ARB_viewport_array,GL_ARB_shader_viewport_layer_array,GL_AMD_vertex_shader_viewport_index,GL_NV_viewport_array2
          --out-path ${GLAD_OUT} c
  COMMENT "Generating the OpenGL 4.5 core loader with glad"
  VERBATIM)
add_library(glad STATIC ${GLAD_OUT}/src/gl.c)
target_include_directories(glad SYSTEM PUBLIC ${GLAD_OUT}/include)
set_target_properties(glad PROPERTIES POSITION_INDEPENDENT_CODE ON)
