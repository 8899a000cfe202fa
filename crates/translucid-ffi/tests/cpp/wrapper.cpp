// The C++ wrapper in use: RAII objects, exceptions with codes, every available method.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>
#include <type_traits>

#include "translucid.hpp"

static_assert(!std::is_copy_constructible<translucid::Mesh>::value, "handles are move-only");
static_assert(std::is_nothrow_move_constructible<translucid::Frame>::value, "handles move");

static int failures = 0;
#define EXPECT(cond)                                                   \
    do {                                                               \
        if (!(cond)) {                                                 \
            std::printf("FAIL line %d: %s\n", __LINE__, #cond);        \
            failures++;                                                \
        }                                                              \
    } while (0)

int main() {
    static const float positions[] = {-5, -5, -2, 5, -5, -2, 5, 5, -2, -5, 5, -2};
    static const std::uint32_t quad[] = {0, 1, 2, 3};
    translucid::Frame kept;
    try {
        translucid::Context context;
        std::printf("device: %s\n", context.device_name().c_str());

        translucid_mesh_create_info mesh_info{};
        mesh_info.primitive = TRANSLUCID_PRIMITIVE_QUADS;
        mesh_info.vertex_count = 4;
        mesh_info.positions = positions;
        mesh_info.index_count = 4;
        mesh_info.indices = quad;
        translucid::Mesh mesh = context.create_mesh(mesh_info);
        translucid::Mesh moved = std::move(mesh);
        EXPECT(!mesh && moved);

        translucid_material_create_info material_info{};
        material_info.base_colour[2] = 1.0f;
        material_info.base_colour[3] = 0.5f;
        translucid::Material blue = context.create_material(material_info);

        translucid_draw draw{};
        draw.mesh = moved.handle();
        draw.material = blue.handle();
        draw.transform[0] = draw.transform[5] = draw.transform[10] = draw.transform[15] = 1.0f;
        translucid_frame_info frame_info{};
        frame_info.width = 8;
        frame_info.height = 4;
        frame_info.camera.view[0] = frame_info.camera.view[5] = 1.0f;
        frame_info.camera.view[10] = frame_info.camera.view[15] = 1.0f;
        frame_info.camera.fov_y = 0.8f;
        frame_info.camera.z_near = 0.5f;
        frame_info.camera.z_far = 10.0f;
        frame_info.draws = &draw;
        frame_info.draw_count = 1;
        for (std::uint32_t method : translucid::Context::available_methods()) {
            frame_info.method = method;
            translucid::Frame frame = context.render(frame_info);
            std::vector<float> linear = frame.read_rgba32f();
            EXPECT(linear.size() == 8 * 4 * 4);
            EXPECT(std::fabs(linear[2] - 0.5f) < 2e-3f);
            EXPECT(frame.read_rgba8().size() == 8 * 4 * 4);
            EXPECT(frame.statistics().method == method);
            EXPECT(frame);
            kept = std::move(frame);  // outlives the Context wrapper below
        }

        // A declared loop, the memory it holds, and a trim that keeps its pipelines.
        {
            frame_info.method = TRANSLUCID_METHOD_EXACT;
            EXPECT(context.prepare(frame_info, TRANSLUCID_CONTENT_ALL) > 0);
            context.render(frame_info);  // builds its own opaque pass, the first time
            EXPECT(context.render(frame_info).statistics().pipelines_created == 0);
            const translucid_memory_statistics memory = context.memory_statistics();
            EXPECT(memory.device_local_bytes > 0 && memory.total_bytes >= memory.device_local_bytes);
            EXPECT(context.trim() > 0);
            EXPECT(context.memory_statistics().total_bytes < memory.total_bytes);
            EXPECT(context.render(frame_info).statistics().pipelines_created == 0);
        }

        // wavelet's loop prepared in the background: once ready, its frames build nothing.
        {
            frame_info.method = TRANSLUCID_METHOD_WAVELET;
            context.prepare_in_background(frame_info, TRANSLUCID_CONTENT_ALL);
            std::uint64_t built = 0;
            while (!context.prepare_ready(&built)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            }
            EXPECT(built > 0);
            EXPECT(context.render(frame_info).statistics().pipelines_created == 0);
        }

        // A mesh moved by update() draws where it was moved: off screen, the pixel is clear.
        {
            static const float away[] = {20, 20, -2, 30, 20, -2, 30, 30, -2, 20, 30, -2};
            frame_info.method = TRANSLUCID_METHOD_EXACT;
            moved.update(0, 4, away);
            EXPECT(context.render(frame_info).read_rgba32f()[2] < 1e-3f);
            moved.update(0, 4, positions);
            EXPECT(std::fabs(context.render(frame_info).read_rgba32f()[2] - 0.5f) < 2e-3f);
        }

        // Errors arrive as exceptions carrying the code and the message.
        mesh_info.vertex_count = 0;
        try {
            translucid::Mesh bad = context.create_mesh(mesh_info);
            EXPECT(false);
        } catch (const translucid::Error &e) {
            EXPECT(e.code() == TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
            EXPECT(std::strstr(e.what(), "vertex_count") != nullptr);
        }
        frame_info.method = 1000;
        try {
            translucid::Frame bad = context.render(frame_info);
            EXPECT(false);
        } catch (const translucid::Error &e) {
            EXPECT(e.code() == TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
        }

        // Host-device mode (tests/c/host.c drives it with a real engine device): the
        // requirements need no device, a standalone context refuses to record, and a host
        // context needs real handles.
        const translucid_host_requirements req = translucid::Context::host_requirements();
        EXPECT(req.api_version >= VK_API_VERSION_1_2 && req.features.shaderInt64 == VK_TRUE);
        const translucid_host_requirements lists =
            translucid::Context::host_requirements(TRANSLUCID_METHOD_LINKED_LIST);
        EXPECT(lists.features.shaderInt64 == VK_TRUE && lists.features.geometryShader == VK_TRUE);
        const translucid_host_subgroup_requirements subgroups =
            translucid::Context::host_subgroup_requirements();
        EXPECT(subgroups.min_size == 8 && subgroups.stages == VK_SHADER_STAGE_COMPUTE_BIT &&
               (subgroups.operations & VK_SUBGROUP_FEATURE_BALLOT_BIT) != 0);
        try {
            translucid::Context::host_requirements(1000);
            EXPECT(false);
        } catch (const translucid::Error &e) {
            EXPECT(e.code() == TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
        }
        frame_info.method = 0;
        try {
            translucid::Frame bad = context.record(frame_info, translucid_host_frame_targets{});
            EXPECT(false);
        } catch (const translucid::Error &e) {
            EXPECT(e.code() == TRANSLUCID_RESULT_ERROR_NOT_SUPPORTED);
        }
        try {
            translucid::Context bad =
                translucid::Context::host(translucid_host_device_create_info{}, 2);
            EXPECT(false);
        } catch (const translucid::Error &e) {
            EXPECT(e.code() == TRANSLUCID_RESULT_ERROR_NULL_POINTER);
        }
    } catch (const translucid::Error &e) {
        std::printf("FAIL: unexpected error %d: %s\n", static_cast<int>(e.code()), e.what());
        return 1;
    }
    // The Context took the frame with it: the wrapper left is empty, and a call on it throws.
    EXPECT(!kept);
    try {
        kept.read_rgba8();
        EXPECT(false);
    } catch (const translucid::Error &e) {
        EXPECT(e.code() == TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
    }
    kept.reset();
    EXPECT(!kept);
    std::printf("wrapper: %d failed\n", failures);
    return failures == 0 ? 0 : 1;
}
