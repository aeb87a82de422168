#pragma once
// The cached level image lit again from a new light map without drawing the level again.
//
// While light maps arrive for the lit view (or AO), the level's draw into the background cache
// also writes two surfaces beside the colour: per pixel where the light map is read (its uv), the
// headlight term, and the surface's colour before light. When then only the light map's texels
// change (a light dragged: the same uvs, a new map), one full-screen pass computes every map-shaded pixel again
// from those surfaces with the very function the level's draw uses (glsl/level_shading.glsl), so the
// picture equals a whole draw's while costing a few texture reads a pixel, not the level's
// triangles (on a software rasteriser most of a frame).

#include "visibility/gl/GlFunctions.h"

namespace sightline::ui {

class LevelRelight {
public:
    explicit LevelRelight(const gl::Functions& gl);
    ~LevelRelight();
    LevelRelight(const LevelRelight&) = delete;
    LevelRelight& operator=(const LevelRelight&) = delete;

    /// Attaches the surfaces, at the cache's size, to `framebuffer` as colour attachments 1 and 2
    /// beside `colour` (its attachment 0, a renderbuffer). False if the framebuffer is incomplete.
    bool attach(GLuint framebuffer, GLuint colour, int width, int height);
    /// Whether the next draws into the framebuffer write the surfaces too (they cost bandwidth,
    /// so only while a map is shown).
    void setWriting(bool on);
    /// Clears the surfaces: nothing there is lit again (the background, until a level draw).
    void clear();
    /// Every map-shaded pixel of the attached colour computed again from the surfaces and the map
    /// bound at texture unit 3; `lit`: the lit view's shading, else AO's.
    void relight(bool lit);

private:
    const gl::Functions& gl_;
    GLuint program_ = 0, vertexArray_ = 0;
    GLuint surface_ = 0, base_ = 0;   ///< textures: (uv, headlight, shaded by the map), colour before light
    GLuint framebuffer_ = 0;          ///< the cache's framebuffer, written through
    GLuint relightFramebuffer_ = 0;   ///< the cache's colour alone: the pass reads the surfaces
    int width_ = 0, height_ = 0;
    bool writing_ = false;

    void release();
};

} // namespace sightline::ui
