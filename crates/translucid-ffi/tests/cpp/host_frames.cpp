// The C++ wrapper on an engine's own device (examples-c/engine.c): frames in flight held as
// RAII Frames, completed or abandoned, each held against the standalone frame of the same
// scene (every pixel within 2/255).
//
// With the argument `drop`, it destroys a frame in flight instead, which must stop the
// program with a message (c_api.rs checks that).
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "../c/checks.h"
#include "translucid.hpp"

namespace {

constexpr std::uint32_t W = 40;
constexpr std::uint32_t H = 30;
constexpr std::size_t COLOUR_BYTES = W * H * 4;
constexpr float BACKGROUND[3] = {0.2f, 0.3f, 0.4f};
constexpr std::uint32_t IN_FLIGHT = 2;

// Three of the test quads, their meshes and materials owned by the wrapper.
struct Scene {
    std::vector<translucid::Mesh> meshes;
    std::vector<translucid::Material> materials;
    std::vector<translucid_draw> draws;

    explicit Scene(translucid::Context &context) {
        static const std::uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
        for (std::size_t i = 0; i < 3; i++) {
            translucid_mesh_create_info mesh{};
            mesh.primitive = TRANSLUCID_PRIMITIVE_TRIANGLES;
            mesh.vertex_count = 4;
            mesh.positions = g_test_quads[i];
            mesh.index_count = 6;
            mesh.indices = triangles;
            meshes.push_back(context.create_mesh(mesh));
            translucid_material_create_info material{};
            material.base_colour[i] = 1.0f;
            material.base_colour[3] = 0.4f + 0.2f * static_cast<float>(i);
            material.flags = TRANSLUCID_MATERIAL_LIT;
            materials.push_back(context.create_material(material));
            translucid_draw draw{};
            draw.mesh = meshes.back().handle();
            draw.material = materials.back().handle();
            draw.layer = TRANSLUCID_LAYER_TRANSPARENT;
            draw.transform[0] = draw.transform[5] = draw.transform[10] = draw.transform[15] = 1.0f;
            draws.push_back(draw);
        }
    }

    // Frame k: quad 2's vertices sway, quad 1 slides; returns the frame's info.
    translucid_frame_info frame(int k) {
        float positions[12];
        std::memcpy(positions, g_test_quads[2], sizeof positions);
        for (int v = 0; v < 4; v++) positions[v * 3 + 1] += 0.07f * static_cast<float>(k);
        meshes[2].update(0, 4, positions);
        draws[1].transform[12] = 0.05f * static_cast<float>(k);
        translucid_frame_info info{};
        info.method = TRANSLUCID_METHOD_EXACT;
        info.width = W;
        info.height = H;
        info.camera.view[0] = info.camera.view[5] = info.camera.view[10] = 1.0f;
        info.camera.view[15] = 1.0f;
        info.camera.view[12] = -0.04f * static_cast<float>(k);
        info.camera.fov_y = 0.9f;
        info.camera.z_near = 1.0f;
        info.camera.z_far = 10.0f;
        info.draws = draws.data();
        info.draw_count = static_cast<std::uint32_t>(draws.size());
        std::memcpy(info.background, BACKGROUND, sizeof BACKGROUND);
        info.frame_index = static_cast<std::uint64_t>(k);
        return info;
    }
};

// One frame in flight's command buffer, fence, images, readback and Frame.
struct Slot {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    VkImage colour = VK_NULL_HANDLE, depth = VK_NULL_HANDLE;
    VkDeviceMemory colour_memory = VK_NULL_HANDLE, depth_memory = VK_NULL_HANDLE;
    VkBuffer readback = VK_NULL_HANDLE;
    VkDeviceMemory readback_memory = VK_NULL_HANDLE;
    void *pixels = nullptr;
    translucid::Frame frame;
    std::vector<std::uint8_t> expected;
};

VkCommandPool g_pool;

void create_slot(Slot &s) {
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = g_pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(g_device, &alloc, &s.cmd));
    VkFenceCreateInfo fence{};
    fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    VK_CHECK(vkCreateFence(g_device, &fence, nullptr, &s.fence));
    const VkImageUsageFlags transfer =
        VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    s.colour = create_image(VK_FORMAT_R8G8B8A8_SRGB,
                            transfer | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, W, H);
    s.colour_memory = bind_image(s.colour);
    s.depth = create_image(VK_FORMAT_D32_SFLOAT,
                           transfer | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                               VK_IMAGE_USAGE_SAMPLED_BIT,
                           W, H);
    s.depth_memory = bind_image(s.depth);
    s.readback = create_host_buffer(COLOUR_BYTES, &s.readback_memory, &s.pixels);
}

void destroy_slot(Slot &s) {
    vkDestroyBuffer(g_device, s.readback, nullptr);
    vkFreeMemory(g_device, s.readback_memory, nullptr);
    vkDestroyImage(g_device, s.colour, nullptr);
    vkFreeMemory(g_device, s.colour_memory, nullptr);
    vkDestroyImage(g_device, s.depth, nullptr);
    vkFreeMemory(g_device, s.depth_memory, nullptr);
    vkDestroyFence(g_device, s.fence, nullptr);
}

// The engine's "opaque pass": colour cleared to the background, depth to the far plane, left
// in the attachment layouts.
void record_opaque(const Slot &s) {
    const VkPipelineStageFlags all = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    const VkAccessFlags any = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    const VkPipelineStageFlags transfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
    const VkImageLayout dst = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    barrier(s.cmd, s.colour, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, dst, all, any,
            transfer, VK_ACCESS_TRANSFER_WRITE_BIT);
    barrier(s.cmd, s.depth, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED, dst, all, any,
            transfer, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkClearColorValue colour{};
    std::memcpy(colour.float32, BACKGROUND, sizeof BACKGROUND);
    colour.float32[3] = 1.0f;
    VkClearDepthStencilValue depth{};
    depth.depth = 1.0f;
    VkImageSubresourceRange range{};
    range.levelCount = 1;
    range.layerCount = 1;
    range.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
    vkCmdClearColorImage(s.cmd, s.colour, dst, &colour, 1, &range);
    range.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT;
    vkCmdClearDepthStencilImage(s.cmd, s.depth, dst, &depth, 1, &range);
    barrier(s.cmd, s.colour, VK_IMAGE_ASPECT_COLOR_BIT, dst,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, transfer, VK_ACCESS_TRANSFER_WRITE_BIT, all,
            any);
    barrier(s.cmd, s.depth, VK_IMAGE_ASPECT_DEPTH_BIT, dst,
            VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, transfer,
            VK_ACCESS_TRANSFER_WRITE_BIT, all, any);
}

translucid_host_frame_targets targets_of(const Slot &s) {
    translucid_host_frame_targets t{};
    t.command_buffer = s.cmd;
    t.colour.image = s.colour;
    t.colour.format = VK_FORMAT_R8G8B8A8_SRGB;
    t.colour.width = t.depth.width = W;
    t.colour.height = t.depth.height = H;
    t.colour.layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    t.colour.final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    t.depth.image = s.depth;
    t.depth.format = VK_FORMAT_D32_SFLOAT;
    t.depth.layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    t.depth.final_layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    return t;
}

// Records the slot's whole frame (opaque, translucid, readback) and submits it.
// With `views`, the frame is recorded as a frame of those views (its info's camera not read).
void record_and_submit(translucid::Context &host, Slot &s, translucid_frame_info info,
                       const std::vector<translucid_frame_view> *views = nullptr) {
    begin_commands(s.cmd);
    record_opaque(s);
    if (views != nullptr) {
        info.camera = translucid_camera{};
        s.frame = host.record(info, targets_of(s), *views);
    } else {
        s.frame = host.record(info, targets_of(s));
    }
    const VkBufferImageCopy colour = region(VK_IMAGE_ASPECT_COLOR_BIT, 0, W, H);
    vkCmdCopyImageToBuffer(s.cmd, s.colour, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, s.readback, 1,
                           &colour);
    VkMemoryBarrier to_host{};
    to_host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(s.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &to_host, 0, nullptr, 0, nullptr);
    submit_commands(s.cmd, s.fence);
}

// The slot's readback within 2/255 of the standalone frame (alpha aside).
void compare(const Slot &s, const char *what) {
    const auto *got = static_cast<const std::uint8_t *>(s.pixels);
    int worst = 0;
    for (std::size_t i = 0; i < COLOUR_BYTES; i++) {
        const int d = std::abs(int(got[i]) - int(s.expected[i]));
        if (i % 4 != 3 && d > worst) worst = d;
    }
    if (worst > 2) std::printf("FAIL %s: %d/255 off the standalone frame\n", what, worst);
    TRUE_OR_FAIL(worst <= 2);
}

// Calls `f`, which must throw translucid::Error with `code`.
template <typename F>
void expect_error(translucid_result code, F f, int line) {
    try {
        f();
        std::printf("FAIL line %d: no error\n", line);
        g_failed++;
    } catch (const translucid::Error &e) {
        if (e.code() != code) std::printf("FAIL line %d: %s\n", line, e.what());
        TRUE_OR_FAIL(e.code() == code);
    }
}

void frames_in_flight(translucid::Context &host, translucid::Context &standalone, Slot *slots,
                      Slot &spare) {
    Scene engine(host), reference(standalone);
    const int frames = 6;
    // Prepared with the slots' image formats, no frame builds a pipeline, the first included.
    const translucid_host_frame_targets like = targets_of(slots[0]);
    translucid_host_image_formats formats{};
    formats.colour_format = like.colour.format;
    formats.colour_layout = like.colour.layout;
    formats.colour_final_layout = like.colour.final_layout;
    formats.depth_format = like.depth.format;
    formats.depth_layout = like.depth.layout;
    formats.depth_final_layout = like.depth.final_layout;
    TRUE_OR_FAIL(host.prepare(engine.frame(0), 0, &formats) > 0);
    for (int k = 0; k < frames; k++) {
        Slot &s = slots[k % IN_FLIGHT];
        if (s.frame) {
            wait_fence(s.fence);
            TRUE_OR_FAIL(s.frame.complete() == translucid::Frame::Completion::done);
            TRUE_OR_FAIL(s.frame.statistics().pipelines_created == 0);
            compare(s, "a frame completed in its turn");
        }
        s.expected = standalone.render(reference.frame(k)).read_rgba8();
        record_and_submit(host, s, engine.frame(k));
    }

    // Both slots are in flight: a third frame is refused, and nothing is recorded.
    begin_commands(spare.cmd);
    expect_error(TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT,
                 [&] { (void)host.record(engine.frame(frames), targets_of(spare)); }, __LINE__);
    VK_CHECK(vkResetCommandBuffer(spare.cmd, 0));

    // Completing the newest completes the older one too: its Frame is then freed without a
    // call of its own, and completing it is an error.
    Slot &older = slots[frames % IN_FLIGHT];
    Slot &newer = slots[(frames + 1) % IN_FLIGHT];
    wait_fence(older.fence);
    wait_fence(newer.fence);
    TRUE_OR_FAIL(newer.frame.complete() == translucid::Frame::Completion::done);
    expect_error(TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT, [&] { (void)older.frame.complete(); },
                 __LINE__);
    compare(older, "an older frame completed by a newer one");
    compare(newer, "the newest frame");
    TRUE_OR_FAIL(older.frame.statistics().frame_index == frames - 2);
    older.frame.reset();
    newer.frame.reset();

    // Abandoning the older of two unsubmitted frames ends both; their command buffers are
    // reset, never submitted.
    for (std::uint32_t i = 0; i < IN_FLIGHT; i++) {
        begin_commands(slots[i].cmd);
        record_opaque(slots[i]);
        slots[i].frame = host.record(engine.frame(frames + 1 + int(i)), targets_of(slots[i]));
    }
    slots[0].frame.abandon();
    TRUE_OR_FAIL(!slots[0].frame);
    expect_error(TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT, [&] { (void)slots[1].frame.complete(); },
                 __LINE__);
    slots[1].frame.reset();
    for (std::uint32_t i = 0; i < IN_FLIGHT; i++) VK_CHECK(vkResetCommandBuffer(slots[i].cmd, 0));

    // The context takes frames again, and they come out right: this one recorded as a frame
    // of views (one, with the frame's camera; the frame info's is left zero).
    Slot &s = slots[0];
    s.expected = standalone.render(reference.frame(frames + 3)).read_rgba8();
    std::vector<translucid_frame_view> views(1);
    views[0].camera = engine.frame(frames + 3).camera;
    record_and_submit(host, s, engine.frame(frames + 3), &views);
    wait_fence(s.fence);
    TRUE_OR_FAIL(s.frame.complete() == translucid::Frame::Completion::done);
    const std::vector<translucid_view_statistics> shares = s.frame.view_statistics();
    TRUE_OR_FAIL(shares.size() == 1 &&
                 shares[0].gpu_milliseconds == s.frame.statistics().gpu_milliseconds);
    compare(s, "a frame after an abandoned pair");
    s.frame.reset();
}

// A frame dropped in flight while an exception unwinds stays in flight, and the program
// goes on; outside unwinding (`drop`), dropping one stops the program.
void dropped_in_flight(translucid::Context &host, Slot &spare, bool unwinding) {
    Scene engine(host);
    begin_commands(spare.cmd);
    if (!unwinding) {
        translucid::Frame frame = host.record(engine.frame(0), targets_of(spare));
        std::printf("dropping a frame in flight\n");
        std::fflush(stdout);
        return;  // the Frame's destructor stops the program
    }
    try {
        translucid::Frame frame = host.record(engine.frame(0), targets_of(spare));
        throw std::runtime_error("the engine's own failure");
    } catch (const std::runtime_error &) {
        g_passed++;
    }
    VK_CHECK(vkResetCommandBuffer(spare.cmd, 0));
}

}  // namespace

int main(int argc, char **argv) {
    const bool drop = argc > 1 && std::strcmp(argv[1], "drop") == 0;
    try {
        const translucid_host_requirements req = translucid::Context::host_requirements();
        create_engine(&req);
        VkCommandPoolCreateInfo pool{};
        pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
        pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pool.queueFamilyIndex = g_family;
        VK_CHECK(vkCreateCommandPool(g_device, &pool, nullptr, &g_pool));
        Slot slots[IN_FLIGHT];
        Slot spare;
        for (Slot &s : slots) create_slot(s);
        create_slot(spare);
        {
            translucid::Context host = translucid::Context::host(host_device_info(), IN_FLIGHT);
            if (drop) {
                dropped_in_flight(host, spare, false);
                return 0;  // not reached
            }
            translucid::Context standalone;
            frames_in_flight(host, standalone, slots, spare);
            dropped_in_flight(host, spare, true);
        }
        for (Slot &s : slots) destroy_slot(s);
        destroy_slot(spare);
        vkDestroyCommandPool(g_device, g_pool, nullptr);
        destroy_engine();
    } catch (const translucid::Error &e) {
        std::printf("FAIL: unexpected error %d: %s\n", static_cast<int>(e.code()), e.what());
        return 1;
    }
    std::printf("host_frames: %d checks passed, %d failed, %d validation messages\n", g_passed,
                g_failed, g_validation_messages);
    return g_failed == 0 && g_validation_messages == 0 ? 0 : 1;
}
