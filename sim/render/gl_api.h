#pragma once

// Internal to incise_render: the OpenGL core API as libOpenGL (glvnd) exports it. Core 3.3+
// entry points are linked directly, so no loader is needed; glvnd dispatches each call to the
// context that EglContext made current. Public headers of this folder must not include this.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
