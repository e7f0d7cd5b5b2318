#pragma once
// OpenGL 3.3 core declarations. Prototypes come from GLVND's libOpenGL (GL_GLEXT_PROTOTYPES
// is set for this library in render/CMakeLists.txt).
#include <GL/glcorearb.h>
