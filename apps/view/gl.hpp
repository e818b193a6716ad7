// OpenGL 3.3 core entry points. Linux's libGL exports every core function, so the prototypes
// are declared here and linked directly, with no loader library.
#pragma once
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
