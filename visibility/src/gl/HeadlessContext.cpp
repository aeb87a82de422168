#include "visibility/gl/HeadlessContext.h"

#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>

#include "base/Error.h"

namespace sightline::gl {

namespace {

class OSMesaContextImpl final : public HeadlessContext {
public:
    OSMesaContextImpl()
    {
        const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0,
                                  OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                                  OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        context_ = OSMesaCreateContextAttribs(attributes, nullptr);
        if (!context_)
            throw Error("OSMesa: cannot create an OpenGL 4.5 core context");
        makeCurrent();
        functions_.load(procAddress());
    }
    ~OSMesaContextImpl() override { OSMesaDestroyContext(context_); }

    void makeCurrent() override
    {
        // A 1x1 default buffer: all rendering goes to framebuffer objects.
        if (!OSMesaMakeCurrent(context_, buffer_, GL_UNSIGNED_BYTE, 1, 1))
            throw Error("OSMesa: cannot make the context current");
    }
    GetProcAddress procAddress() const override
    {
        return [](const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); };
    }

private:
    OSMesaContext context_ = nullptr;
    unsigned char buffer_[4] = {};
};

class EglContextImpl final : public HeadlessContext {
public:
    EglContextImpl()
    {
        // Prefer a GPU device (EGL_EXT_platform_device), then Mesa's surfaceless platform.
        auto getPlatformDisplay =
            reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
        auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        if (getPlatformDisplay && queryDevices) {
            EGLDeviceEXT devices[16];
            EGLint count = 0;
            if (queryDevices(16, devices, &count))
                for (EGLint i = 0; i < count && display_ == EGL_NO_DISPLAY; ++i)
                    tryDisplay(getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr));
        }
        if (display_ == EGL_NO_DISPLAY && getPlatformDisplay)
            tryDisplay(getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
        if (display_ == EGL_NO_DISPLAY)
            throw Error("EGL: no display offers an OpenGL 4.5 core context");
        makeCurrent();
        functions_.load(procAddress());
    }
    ~EglContextImpl() override
    {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        eglTerminate(display_);
    }

    void makeCurrent() override
    {
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
            throw Error("EGL: cannot make the context current (surfaceless contexts unsupported?)");
    }
    GetProcAddress procAddress() const override
    {
        return [](const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); };
    }

private:
    void tryDisplay(EGLDisplay display)
    {
        if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr))
            return;
        const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint configs = 0;
        if (!eglBindAPI(EGL_OPENGL_API) || !eglChooseConfig(display, configAttributes, &config, 1, &configs) ||
            configs < 1) {
            // Surfaceless displays may offer no pbuffer config; contexts without a config work
            // with EGL_KHR_no_config_context.
            config = EGL_NO_CONFIG_KHR;
        }
        const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                            EGL_NONE};
        EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
        if (context == EGL_NO_CONTEXT) {
            eglTerminate(display);
            return;
        }
        display_ = display;
        context_ = context;
    }

    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
};

} // namespace

std::string HeadlessContext::renderer() const
{
    const auto* text = reinterpret_cast<const char*>(functions_.GetString(GL_RENDERER));
    return text ? text : "unknown";
}

std::unique_ptr<HeadlessContext> HeadlessContext::create(Backend backend)
{
    if (backend == Backend::Egl)
        return std::make_unique<EglContextImpl>();
    return std::make_unique<OSMesaContextImpl>();
}

std::function<std::unique_ptr<HeadlessContext>()> contextFactory(Backend backend)
{
    return [backend] { return HeadlessContext::create(backend); };
}

Backend parseBackend(const std::string& name)
{
    if (name == "osmesa")
        return Backend::OSMesa;
    if (name == "egl")
        return Backend::Egl;
    throw Error("unknown GL backend '" + name + "' (osmesa, egl)");
}

} // namespace sightline::gl
