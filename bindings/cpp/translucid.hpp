// translucid.hpp: a header-only C++17 RAII wrapper over the C API in translucid.h.
//
// Errors are reported by exceptions: every failing call throws translucid::Error, which carries
// the result code and the context's last-error message. (An expected-style result would make
// every call site check; exceptions keep the happy path a straight line, and engines that
// build without exceptions can use the C API directly.) Status codes that are not errors are
// handled inside the wrapper (TRANSLUCID_RESULT_INCOMPLETE) or returned as an enum
// (Frame::complete's Completion).
//
// Ownership: Context, Mesh, Texture, Material and Frame are move-only. The Context owns the C
// context, and destroying it destroys the C context and every object made with it there and
// then, so that an engine destroys it before its VkDevice whatever objects it still holds.
// Objects that outlive their Context are empty: destroying them does nothing, and calls on
// them throw TRANSLUCID_RESULT_ERROR_STALE_HANDLE. As with the C API, one context and its
// objects must be used by one thread at a time.
//
// Frames in flight (host-device mode) must be completed or abandoned: the wrapper cannot tell
// whether the GPU still runs a recorded frame, so it can neither free one nor end its flight.
// Destroying a Frame that is still in flight prints why to stderr and calls std::abort(), as
// destroying a joinable std::thread terminates; while an exception unwinds, the frame is left
// in flight in its context instead (freed with the context).
//
//   translucid::Context context;                       // standalone mode, own device
//   translucid::Mesh quad = context.create_mesh(mesh_info);
//   translucid::Frame frame = context.render(frame_info);
//   frame.write_png("out/frame.png");
#ifndef TRANSLUCID_HPP
#define TRANSLUCID_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "translucid.h"

namespace translucid {

/// A failed call: the code (negative, a TRANSLUCID_RESULT_ERROR_*) and the message.
class Error : public std::runtime_error {
public:
    Error(translucid_result code, const std::string &message)
        : std::runtime_error(message), code_(code) {}
    translucid_result code() const noexcept { return code_; }

private:
    translucid_result code_;
};

namespace detail {

using ContextPtr = std::shared_ptr<translucid_context>;
/// What an object keeps of its context: it does not keep it alive.
using ContextRef = std::weak_ptr<translucid_context>;

inline void check(translucid_result result, const translucid_context *context, const char *call) {
    if (result < 0) {
        throw Error(result, std::string(call) + ": " + translucid_result_string(result) + ": " +
                                translucid_context_get_last_error(context));
    }
}

// A move-only handle that destroys its object when it goes out of scope.
template <typename Handle, translucid_result (*Destroy)(translucid_context *, Handle)>
class Object {
public:
    Object() noexcept : handle_{0} {}
    Object(const ContextPtr &context, Handle handle) noexcept
        : context_(context), handle_(handle) {}
    Object(const Object &) = delete;
    Object &operator=(const Object &) = delete;
    Object(Object &&other) noexcept
        : context_(std::move(other.context_)), handle_(std::exchange(other.handle_, Handle{0})) {}
    Object &operator=(Object &&other) noexcept {
        if (this != &other) {
            reset();
            context_ = std::move(other.context_);
            handle_ = std::exchange(other.handle_, Handle{0});
        }
        return *this;
    }
    ~Object() { reset(); }

    /// The C handle, for use with the C API (still owned by this object).
    Handle handle() const noexcept { return handle_; }
    /// False when empty: moved from, reset, or its Context destroyed.
    explicit operator bool() const noexcept { return handle_.id != 0 && !context_.expired(); }

    /// Destroys the object now. Errors are ignored: destroying fails only for a handle the
    /// wrapper never hands out, or for a host-device frame in flight (see the top of this
    /// file). Nothing to do once its Context is destroyed, which destroyed the object too.
    void reset() noexcept {
        if (handle_.id != 0) {
            if (const ContextPtr context = context_.lock()) {
                Destroy(context.get(), handle_);
            }
        }
        handle_ = Handle{0};
        context_.reset();
    }

protected:
    /// The C context; throws TRANSLUCID_RESULT_ERROR_STALE_HANDLE once the Context is gone.
    translucid_context *context() const {
        // The Context holds the only owning reference, so the pointer stays valid while it
        // lives, past this temporary.
        const ContextPtr context = context_.lock();
        if (!context) {
            throw Error(TRANSLUCID_RESULT_ERROR_STALE_HANDLE,
                        "the translucid::Context that made this object was destroyed, and the "
                        "object with it");
        }
        return context.get();
    }
    /// Forgets the handle without destroying it (the C API has freed it already).
    void release() noexcept {
        handle_ = Handle{0};
        context_.reset();
    }

private:
    ContextRef context_;
    Handle handle_;
};

/// Frees a frame, unless it is in flight: then, outside exception unwinding, stops the
/// program, since a frame dropped in flight is a bug the engine would otherwise find as a
/// frame-in-flight error many frames later.
inline translucid_result destroy_frame(translucid_context *context, translucid_frame frame) {
    const translucid_result r = translucid_frame_destroy(context, frame);
    if (r == TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT && std::uncaught_exceptions() == 0) {
        std::fprintf(stderr,
                     "translucid::Frame destroyed while in flight: call complete() once its "
                     "submission finished, or abandon() if the GPU never runs it\n");
        std::abort();
    }
    return r;
}

}  // namespace detail

/// A mesh: uploaded once, drawn by handle; its vertices can move every frame.
class Mesh : public detail::Object<translucid_mesh, translucid_mesh_destroy> {
public:
    using Object::Object;

    /// Moves `count` vertices from `first` to `positions` (count x 3 floats) for the frames
    /// recorded after the call (translucid_mesh_update).
    void update(std::uint32_t first, std::uint32_t count, const float *positions) {
        detail::check(translucid_mesh_update(context(), handle(), first, count, positions),
                      context(), "translucid_mesh_update");
    }
};

using Texture = detail::Object<translucid_texture, translucid_texture_destroy>;
using Material = detail::Object<translucid_material, translucid_material_destroy>;

/// A rendered frame (its pixels, a PNG writer and its statistics), or a recorded one in
/// flight until complete() or abandon().
class Frame : public detail::Object<translucid_frame, detail::destroy_frame> {
public:
    using Object::Object;

    /// sRGB RGBA8, rows top first.
    std::vector<std::uint8_t> read_rgba8() const {
        return read<std::uint8_t>(TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, 4);
    }
    /// Linear RGBA floats, rows top first.
    std::vector<float> read_rgba32f() const {
        return read<float>(TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR, 4);
    }
    void write_png(const std::string &path) const {
        detail::check(translucid_frame_write_png(context(), handle(), path.c_str()), context(),
                      "translucid_frame_write_png");
    }
    /// What Frame::complete found.
    enum class Completion {
        done,       ///< the colour image holds the frame
        degraded,   ///< past a limit, rows kept the opaque colour: restore it, record again
        not_ready,  ///< the commands have not run: the frame stays in flight
    };
    /// Host-device mode: call once the host waited for the engine's submission of the frame
    /// (completing it completes the older frames in flight too, whose Frames then need no
    /// call of their own). Throws for a frame not in flight, or when the method failed (the
    /// flight is over either way).
    [[nodiscard]] Completion complete() {
        const translucid_result r = translucid_frame_complete(context(), handle());
        detail::check(r, context(), "translucid_frame_complete");
        if (r == TRANSLUCID_RESULT_NOT_READY) return Completion::not_ready;
        if (r == TRANSLUCID_RESULT_FRAME_DEGRADED) return Completion::degraded;
        return Completion::done;
    }
    /// Host-device mode: ends the flight of a frame the GPU is not running and never will
    /// (never submitted, or its results unwanted), and frees it; the frames recorded after
    /// it end too (translucid_frame_abandon).
    void abandon() {
        detail::check(translucid_frame_abandon(context(), handle()), context(),
                      "translucid_frame_abandon");
        release();
    }
    translucid_frame_statistics statistics() const {
        translucid_frame_statistics stats{};
        stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
        detail::check(translucid_frame_get_statistics(context(), handle(), &stats), context(),
                      "translucid_frame_get_statistics");
        return stats;
    }
    /// Each view's share of the frame (translucid_frame_view_statistics; one for a frame of
    /// one view).
    std::vector<translucid_view_statistics> view_statistics() const {
        translucid_frame_view_statistics shares{};
        shares.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_VIEW_STATISTICS;
        translucid_frame_statistics stats{};
        stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
        stats.next = &shares;
        detail::check(translucid_frame_get_statistics(context(), handle(), &stats), context(),
                      "translucid_frame_get_statistics");
        return std::vector<translucid_view_statistics>(shares.views,
                                                       shares.views + shares.view_count);
    }

private:
    template <typename T>
    std::vector<T> read(std::uint32_t format, std::size_t per_pixel) const {
        const translucid_frame_statistics stats = statistics();
        std::vector<T> pixels(std::size_t(stats.width) * stats.height * per_pixel);
        detail::check(translucid_frame_read(context(), handle(), format, pixels.data(),
                                            pixels.size() * sizeof(T)),
                      context(), "translucid_frame_read");
        return pixels;
    }
};

/// Options for a standalone context.
struct ContextOptions {
    /// Device index or name substring; empty uses TRANSLUCID_DEVICE or the best device.
    std::string device;
    /// Khronos validation layer on (TRANSLUCID_VALIDATION=1 also turns it on).
    bool validation = false;
};

/// A context: translucid's own headless device (standalone), or the engine's (host device,
/// from Context::host).
class Context {
public:
    /// What the engine's instance and device must have (call before creating them).
    static translucid_host_requirements host_requirements() {
        translucid_host_requirements req{};
        req.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS;
        detail::check(translucid_host_get_requirements(&req), nullptr,
                      "translucid_host_get_requirements");
        return req;
    }
    /// The same for an engine that uses `method`: every method's features and the method's
    /// own (OR together those of the methods you use).
    static translucid_host_requirements host_requirements(std::uint32_t method) {
        translucid_host_requirements req{};
        req.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS;
        detail::check(translucid_host_get_method_requirements(method, &req), nullptr,
                      "translucid_host_get_method_requirements");
        return req;
    }
    /// What exact and wavelet need of the device's subgroups, to pick a physical device by
    /// (translucid_host_subgroup_requirements).
    static translucid_host_subgroup_requirements host_subgroup_requirements() {
        translucid_host_subgroup_requirements subgroups{};
        subgroups.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_SUBGROUP_REQUIREMENTS;
        translucid_host_requirements req{};
        req.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS;
        req.next = &subgroups;
        detail::check(translucid_host_get_requirements(&req), nullptr,
                      "translucid_host_get_requirements");
        return subgroups;
    }
    /// A context on the engine's device, taking up to `frames_in_flight` frames recorded and
    /// not completed, each of up to `views_per_frame` views (record with views); `s_type` is
    /// filled in for you. Destroy the Context before the engine's device: that destroys every
    /// object made with it, whichever wrappers the engine still holds.
    static Context host(translucid_host_device_create_info device,
                        std::uint32_t frames_in_flight = 1, std::uint32_t views_per_frame = 1) {
        device.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_DEVICE_CREATE_INFO;
        translucid_host_views_create_info views{};
        views.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_VIEWS_CREATE_INFO;
        views.next = device.next;
        views.views_per_frame = views_per_frame;
        device.next = &views;
        translucid_context_create_info info{};
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
        info.header_version = TRANSLUCID_HEADER_VERSION;
        info.mode = TRANSLUCID_CONTEXT_MODE_HOST_DEVICE;
        info.next = &device;
        info.frames_in_flight = frames_in_flight;
        return Context(info);
    }

    explicit Context(const ContextOptions &options = ContextOptions()) {
        translucid_context_create_info info{};
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
        info.header_version = TRANSLUCID_HEADER_VERSION;
        info.mode = TRANSLUCID_CONTEXT_MODE_STANDALONE;
        info.flags = options.validation ? TRANSLUCID_CONTEXT_CREATE_VALIDATION : 0u;
        info.device = options.device.empty() ? nullptr : options.device.c_str();
        create(info);
    }
    Context(const Context &) = delete;
    Context &operator=(const Context &) = delete;
    Context(Context &&) noexcept = default;
    Context &operator=(Context &&) noexcept = default;

    /// The C context (owned by this wrapper alone).
    translucid_context *get() const noexcept { return context_.get(); }
    std::string device_name() const { return translucid_context_get_device_name(context_.get()); }

    /// Creates objects from C create-infos; `s_type` is filled in for you.
    Mesh create_mesh(translucid_mesh_create_info info) {
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
        translucid_mesh mesh{0};
        detail::check(translucid_mesh_create(get(), &info, &mesh), get(),
                      "translucid_mesh_create");
        return Mesh(context_, mesh);
    }
    Texture create_texture(translucid_texture_create_info info) {
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
        translucid_texture texture{0};
        detail::check(translucid_texture_create(get(), &info, &texture), get(),
                      "translucid_texture_create");
        return Texture(context_, texture);
    }
    Material create_material(translucid_material_create_info info) {
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
        translucid_material material{0};
        detail::check(translucid_material_create(get(), &info, &material), get(),
                      "translucid_material_create");
        return Material(context_, material);
    }
    /// Declares what the loop's frames may draw (TRANSLUCID_CONTENT_* bits) and builds now
    /// every pipeline frames like `frame` need (translucid_context_prepare), and with
    /// `formats` (host-device mode) those of the passes made for the engine's images; returns
    /// how many it built.
    std::uint64_t prepare(translucid_frame_info frame, std::uint32_t content,
                          const translucid_host_image_formats *formats = nullptr) {
        std::uint64_t built = 0;
        with_prepare_info(frame, content, formats, [&](const translucid_prepare_info &info) {
            detail::check(translucid_context_prepare(get(), &info, &built), get(),
                          "translucid_context_prepare");
        });
        return built;
    }
    /// The same on a thread of translucid's own, while the loop goes on
    /// (translucid_context_prepare_in_background); `prepare_ready` says when it is in effect.
    void prepare_in_background(translucid_frame_info frame, std::uint32_t content,
                               const translucid_host_image_formats *formats = nullptr) {
        with_prepare_info(frame, content, formats, [&](const translucid_prepare_info &info) {
            detail::check(translucid_context_prepare_in_background(get(), &info), get(),
                          "translucid_context_prepare_in_background");
        });
    }
    /// Whether no preparation runs in the background any more, all of it in effect
    /// (translucid_context_get_prepare_status, which alone puts finished work in effect:
    /// call it between frames); `built` (may be null) receives the pipelines it built since
    /// the last call. Throws the error such work ended with (other work goes on).
    bool prepare_ready(std::uint64_t *built = nullptr) {
        const translucid_result status = translucid_context_get_prepare_status(get(), built);
        if (status == TRANSLUCID_RESULT_NOT_READY) return false;
        detail::check(status, get(), "translucid_context_get_prepare_status");
        return true;
    }
    /// The GPU memory the context holds, by kind (translucid_context_get_memory_statistics).
    translucid_memory_statistics memory_statistics() const {
        translucid_memory_statistics memory{};
        memory.s_type = TRANSLUCID_STRUCTURE_TYPE_MEMORY_STATISTICS;
        detail::check(translucid_context_get_memory_statistics(get(), &memory), get(),
                      "translucid_context_get_memory_statistics");
        return memory;
    }
    /// Gives back what no frame in flight uses (translucid_context_trim); the bytes freed.
    std::uint64_t trim() {
        std::uint64_t freed = 0;
        detail::check(translucid_context_trim(get(), &freed), get(), "translucid_context_trim");
        return freed;
    }

    /// Renders one frame. Method settings are chained to `info.next` as in C
    /// (`translucid_wavelet_settings` and the like; without one, a method takes its defaults).
    Frame render(translucid_frame_info info) {
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
        translucid_frame frame{0};
        detail::check(translucid_frame_render(get(), &info, &frame), get(),
                      "translucid_frame_render");
        return Frame(context_, frame);
    }

    /// Host-device mode: records a frame into `targets.command_buffer`; submit it, and call
    /// Frame::complete once you waited for it (or Frame::abandon if you never submit it)
    /// before the Frame is destroyed. Up to the context's frames_in_flight frames may be in
    /// flight.
    [[nodiscard]] Frame record(translucid_frame_info info, translucid_host_frame_targets targets) {
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
        targets.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_TARGETS;
        translucid_frame frame{0};
        detail::check(translucid_frame_record(get(), &info, &targets, &frame), get(),
                      "translucid_frame_record");
        return Frame(context_, frame);
    }

    /// Host-device mode: records one frame of several views (stereo, a split screen), each
    /// with its own camera, layer and corner in the targets' images, whose layer counts are
    /// `colour_layers` and `depth_layers` (translucid_host_frame_views, chained to `targets`
    /// in place of anything chained there; `info.camera` is not read). The frame is one
    /// frame in flight and completes once.
    [[nodiscard]] Frame record(translucid_frame_info info, translucid_host_frame_targets targets,
                               const std::vector<translucid_frame_view> &views,
                               std::uint32_t colour_layers = 1, std::uint32_t depth_layers = 1) {
        translucid_host_frame_views chain{};
        chain.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_VIEWS;
        chain.colour_layer_count = colour_layers;
        chain.depth_layer_count = depth_layers;
        chain.view_count = static_cast<std::uint32_t>(views.size());
        chain.views = views.data();
        targets.next = &chain;
        return record(info, targets);
    }

    /// Host-device mode, for measuring: records native_blend, the yardstick (the engine's
    /// own unsorted blend of the same draws, straight into its images), as a Frame like
    /// record's (translucid_frame_record_native_blend).
    [[nodiscard]] Frame record_native_blend(translucid_frame_info info,
                                            translucid_host_frame_targets targets) {
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
        targets.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_TARGETS;
        translucid_frame frame{0};
        detail::check(translucid_frame_record_native_blend(get(), &info, &targets, &frame),
                      get(), "translucid_frame_record_native_blend");
        return Frame(context_, frame);
    }

    /// The methods this build has (translucid_method values).
    static std::vector<std::uint32_t> available_methods() {
        std::size_t count = 0;
        translucid_result r = translucid_method_get_available(nullptr, 0, &count);
        detail::check(r, nullptr, "translucid_method_get_available");
        std::vector<std::uint32_t> methods(count);
        r = translucid_method_get_available(methods.data(), methods.size(), &count);
        detail::check(r, nullptr, "translucid_method_get_available");
        methods.resize(count < methods.size() ? count : methods.size());
        return methods;
    }

private:
    explicit Context(const translucid_context_create_info &info) { create(info); }
    void create(const translucid_context_create_info &info) {
        translucid_context *raw = nullptr;
        detail::check(translucid_context_create(&info, &raw), nullptr,
                      "translucid_context_create");
        context_ = detail::ContextPtr(raw, translucid_context_destroy);
    }
    // Calls `use` with a prepare info for `frame` and `content`, `formats` chained if given.
    template <typename Use>
    static void with_prepare_info(translucid_frame_info frame, std::uint32_t content,
                                  const translucid_host_image_formats *formats, Use use) {
        frame.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
        translucid_host_image_formats chained{};
        if (formats != nullptr) {
            chained = *formats;
            chained.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_FORMATS;
            chained.next = nullptr;
        }
        translucid_prepare_info info{};
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_PREPARE_INFO;
        info.next = formats != nullptr ? &chained : nullptr;
        info.frame = &frame;
        info.content = content;
        use(info);
    }

    detail::ContextPtr context_;
};

}  // namespace translucid

#endif  // TRANSLUCID_HPP
