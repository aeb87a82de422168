#pragma once
// What the headless renderer's tests share: a level whose surfaces hide one another, and the
// picture a render target holds.

#include <cmath>
#include <string>

#include <QImage>

#include "TestScenes.h"
#include "editor/ViewportRenderer.h"
#include "visibility/Scene.h"
#include "visibility/gl/GlFunctions.h"

namespace sightline::test {

/// A rolling sheet of n x n quads and a tilted plane through it: 2 n^2 + 2 triangles, surfaces
/// that cross, so that what is drawn later must be depth-tested against what was drawn before.
inline Scene crossingSheets(int n)
{
    Mesh sheet = heightGrid("sheet", n, 10.0f, [](float x, float z) { return std::sin(x * 0.7f) * std::cos(z * 0.5f); });
    Mesh plane;
    plane.name = "plane";
    plane.positions = {{-10.0f, -2.0f, -10.0f}, {10.0f, -2.0f, -10.0f}, {10.0f, 2.0f, 10.0f}, {-10.0f, 2.0f, 10.0f}};
    plane.indices = {0, 2, 1, 0, 3, 2};
    Scene scene;
    scene.addMeshInstance(std::move(sheet));
    scene.addMeshInstance(std::move(plane));
    return scene;
}

/// The colour `target` holds, row 0 at the bottom (as GL reads it).
inline QImage readBack(const gl::Functions& gl, const ui::RenderTarget& target)
{
    QImage image(target.width, target.height, QImage::Format_RGBA8888);
    gl.BindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.ReadPixels(0, 0, target.width, target.height, GL_RGBA, GL_UNSIGNED_BYTE, image.bits());
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    return image;
}

} // namespace sightline::test
