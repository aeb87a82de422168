#include "OffscreenRender.h"

#include "EditorDocument.h"
#include "editor/LitPreview.h"
#include "editor/RayEnds.h"
#include "base/Error.h"

namespace sightline::ui {

OffscreenResult renderOffscreen(const EditorDocument& document, const Camera& camera, const ViewStyle& style, int width,
                                int height, gl::Backend backend, PatchOverlay* overlay, const Approximation* disagreement)
{
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw Error("image size must be between 1x1 and 16384x16384");
    const auto context = gl::HeadlessContext::create(backend);
    const gl::Functions& gl = context->functions();

    RenderTarget target;
    if (!target.create(gl, width, height))
        throw Error("screenshot: the offscreen framebuffer is incomplete");
    const GLuint fbo = target.framebuffer;

    OffscreenResult result;
    {
        ViewportRenderer renderer(gl);
        renderer.setSceneFile(document.sceneFile());
        renderer.setOccluders(document.occluderScene(), document.occluderOfInstance());
        if (style.litView) {   // the exact lit view, as the editor shows it once converged
            const LitPreviewFrame lit = exactLitFrame(std::make_shared<const Scene>(document.scene()), document.lights(),
                                                      style.litShading, style.litBudget, style.litIndirect);
            if (!lit.error.empty())
                throw Error("lit view: " + lit.error);
            renderer.setAmbientOcclusion(*lit.uvs, lit.width, lit.height, lit.map);
        }
        LiveVisibility visibility;
        visibility.setScene(document.rayScene());
        const Project& project = document.project();
        visibility.loadReceiverHeights(project, document.displayName().toStdString());
        result.visibility = visibility.sample(project.source, project.receiver);
        renderer.setHiddenSamples(result.visibility.valid ? &result.visibility.map : nullptr);
        if (result.visibility.valid && style.showBlocked && style.showRays) {
            // Blocked rays end where they are first stopped, as in the editor.
            const pvs::FirstHitCaster hits(document.scene());
            const HiddenSampleMap& map = result.visibility.map;
            result.visibility.rayEnds = drawnRayEnds(hits, map, project.source, project.receiver,
                                                     raySubset(map.sourceCount(), map.receiverCount(), style.rayCap));
            result.visibility.rayEndsCap = style.rayCap;
            renderer.setRayEnds(result.visibility.rayEnds, style.rayCap);
        }
        if (disagreement && result.visibility.valid) {
            ApproximateSampler sampler(*disagreement, document.rayScene());
            const ReceiverHeights& heights = visibility.receiverHeights();
            result.disagreement = judgedDisagreement(sampler, document.rayScene(), project.source, project.receiver, &heights,
                                                     result.visibility.map, 0, &gl);
            renderer.setDisagreement(&result.disagreement->disagreement);
        }
        if (overlay) {
            overlay->setLive(result.visibility, project, true);
            renderer.setOverlay(overlayPatch(overlay->kind()), &overlay->texels());
        }

        FrameState frame;
        frame.camera = camera;
        frame.width = width;
        frame.height = height;
        frame.framebuffer = fbo;
        const Bounds bounds = document.scene().bounds();
        frame.sceneRadius = bounds.empty() ? 10.0 : 0.5 * glm::length(bounds.max - bounds.min);
        frame.source = project.source;
        frame.receiver = project.receiver;
        frame.pairValid = result.visibility.valid;
        frame.selection = document.selection();   // the image shows what the editor shows
        frame.lights = document.lights();
        frame.sunLevel = document.levelBounds();
        frame.style = style;
        renderer.render(frame);
        result.raysDrawn = renderer.raysDrawn();

        QImage image(width, height, QImage::Format_RGBA8888);
        gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
        gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
        gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.bits());
        gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        result.image = image.mirrored().convertToFormat(QImage::Format_RGB32);   // GL rows run bottom-up
    }
    target.destroy(gl);
    return result;
}

} // namespace sightline::ui
