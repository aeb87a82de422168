#pragma once
// Headless OpenGL 4.5 core contexts for batch work and tests: OSMesa (software, llvmpipe; the
// default, works anywhere Mesa is installed) and EGL surfaceless (real GPUs on servers). The
// context renders only into framebuffer objects; it owns no window.

#include <functional>
#include <memory>
#include <string>

#include "visibility/gl/GlFunctions.h"

namespace sightline::gl {

enum class Backend { OSMesa, Egl };

class HeadlessContext {
public:
    virtual ~HeadlessContext() = default;
    /// Makes the context current on the calling thread.
    virtual void makeCurrent() = 0;
    virtual GetProcAddress procAddress() const = 0;
    /// The resolved functions, loaded once the context was first made current.
    const Functions& functions() const { return functions_; }
    /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string renderer() const;

    /// Creates and makes current a 4.5 core context. Throws sightline::Error with the reason
    /// (library missing, no 4.5 core profile, no display device).
    static std::unique_ptr<HeadlessContext> create(Backend backend = Backend::OSMesa);

protected:
    Functions functions_;
};

Backend parseBackend(const std::string& name);   ///< "osmesa" or "egl"; throws otherwise

/// HeadlessContext::create(backend) as a factory, for code that is handed the means to make a
/// context rather than linking the contexts itself (project/ProjectSampler.h).
std::function<std::unique_ptr<HeadlessContext>()> contextFactory(Backend backend);

} // namespace sightline::gl
