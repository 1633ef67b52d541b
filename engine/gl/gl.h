#pragma once
// The one include for OpenGL 4.5 core in the project (glad, generated into the build tree).
#include <glad/gl.h>
