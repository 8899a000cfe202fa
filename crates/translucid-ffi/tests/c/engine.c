/* The host-device tests' engine: see engine.h. */
#include "engine.h"

int g_failed = 0, g_passed = 0, g_validation_messages = 0;
VkInstance g_instance;
VkPhysicalDevice g_physical;
VkDevice g_device;
VkQueue g_queue;
uint32_t g_family;
VkPhysicalDeviceFeatures g_features;
static VkDebugUtilsMessengerEXT g_messenger;

void fail(const char *what, int line) {
    printf("FAIL line %d: %s\n", line, what);
    exit(1);
}

void check(translucid_context *ctx, translucid_result got, translucid_result want,
                  const char *call, int line) {
    if (got != want) {
        printf("FAIL line %d: %s returned %s (%d), expected %s: %s\n", line, call,
               translucid_result_string(got), got, translucid_result_string(want),
               translucid_context_last_error(ctx));
        g_failed++;
        if (want == TRANSLUCID_RESULT_SUCCESS) exit(1);
    } else {
        g_passed++;
    }
}
static VKAPI_ATTR VkBool32 VKAPI_CALL on_validation(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT type,
    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user) {
    (void)type;
    (void)user;
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        printf("VALIDATION: %s\n", data->pMessage);
        g_validation_messages++;
    }
    return VK_FALSE;
}

int env_is_1(const char *name) {
    const char *v = getenv(name);
    return v != NULL && strcmp(v, "1") == 0;
}

void create_instance(uint32_t api_version) {
    const char *layers[] = {"VK_LAYER_KHRONOS_validation"};
    const char *extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features;
    VkApplicationInfo app;
    VkInstanceCreateInfo info;
    VkDebugUtilsMessengerCreateInfoEXT messenger;
    int validate = env_is_1("TRANSLUCID_VALIDATION");

    memset(&app, 0, sizeof app);
    app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
    app.pApplicationName = "translucid host test";
    app.apiVersion = api_version;
    memset(&features, 0, sizeof features);
    features.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    memset(&info, 0, sizeof info);
    info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
    info.pApplicationInfo = &app;
    if (validate) {
        info.pNext = env_is_1("TRANSLUCID_SYNC_VALIDATION") ? &features : NULL;
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = layers;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = extensions;
    }
    VK_CHECK(vkCreateInstance(&info, NULL, &g_instance));
    if (validate) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                g_instance, "vkCreateDebugUtilsMessengerEXT");
        memset(&messenger, 0, sizeof messenger);
        messenger.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
        messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
        messenger.pfnUserCallback = on_validation;
        if (create == NULL) fail("vkCreateDebugUtilsMessengerEXT not found", __LINE__);
        VK_CHECK(create(g_instance, &messenger, NULL, &g_messenger));
    }
}

/* The first device and queue family that meet the requirements, and the device made with
 * exactly the features translucid asks for. */
void create_device(const translucid_host_requirements *req) {
    VkPhysicalDevice devices[8];
    uint32_t count = 8, i;
    VkQueueFamilyProperties families[16];
    uint32_t family_count = 16;
    VkPhysicalDeviceProperties properties;
    VkPhysicalDeviceFeatures supported;
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue;
    VkDeviceCreateInfo info;
    VkResult r = vkEnumeratePhysicalDevices(g_instance, &count, devices);

    if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || count == 0) fail("no Vulkan device", __LINE__);
    g_physical = devices[0];
    vkGetPhysicalDeviceProperties(g_physical, &properties);
    TRUE_OR_FAIL(properties.apiVersion >= req->api_version);
    vkGetPhysicalDeviceQueueFamilyProperties(g_physical, &family_count, families);
    g_family = family_count;
    for (i = 0; i < family_count; i++) {
        if ((families[i].queueFlags & req->queue_flags) == req->queue_flags &&
            families[i].timestampValidBits > 0) {
            g_family = i;
            break;
        }
    }
    if (g_family == family_count) fail("no queue family meets the requirements", __LINE__);

    /* An engine ORs the requirements into its own features; this one has none of its own. */
    vkGetPhysicalDeviceFeatures(g_physical, &supported);
    g_features = req->features;
    TRUE_OR_FAIL(g_features.shaderInt64 == VK_TRUE && supported.shaderInt64 == VK_TRUE);
    TRUE_OR_FAIL(g_features.dualSrcBlend == VK_TRUE && supported.dualSrcBlend == VK_TRUE);

    memset(&queue, 0, sizeof queue);
    queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
    queue.queueFamilyIndex = g_family;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    memset(&info, 0, sizeof info);
    info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    info.pEnabledFeatures = &g_features;
    info.enabledExtensionCount = req->extension_count;
    info.ppEnabledExtensionNames = req->extensions;
    VK_CHECK(vkCreateDevice(g_physical, &info, NULL, &g_device));
    vkGetDeviceQueue(g_device, g_family, 0, &g_queue);
}

uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags wanted) {
    VkPhysicalDeviceMemoryProperties props;
    uint32_t i;
    vkGetPhysicalDeviceMemoryProperties(g_physical, &props);
    for (i = 0; i < props.memoryTypeCount; i++) {
        if ((bits & (1u << i)) && (props.memoryTypes[i].propertyFlags & wanted) == wanted) {
            return i;
        }
    }
    fail("no suitable memory type", __LINE__);
    return 0;
}

VkDeviceMemory bind_image(VkImage image) {
    VkMemoryRequirements req;
    VkMemoryAllocateInfo info;
    VkDeviceMemory memory;
    vkGetImageMemoryRequirements(g_device, image, &req);
    memset(&info, 0, sizeof info);
    info.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    info.allocationSize = req.size;
    info.memoryTypeIndex = memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VK_CHECK(vkAllocateMemory(g_device, &info, NULL, &memory));
    VK_CHECK(vkBindImageMemory(g_device, image, memory, 0));
    return memory;
}

VkImage create_image(VkFormat format, VkImageUsageFlags usage, uint32_t width, uint32_t height) {
    VkImageCreateInfo info;
    VkImage image;
    memset(&info, 0, sizeof info);
    info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent.width = width;
    info.extent.height = height;
    info.extent.depth = 1;
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(g_device, &info, NULL, &image));
    return image;
}

VkBuffer create_host_buffer(VkDeviceSize size, VkDeviceMemory *memory, void **mapped) {
    VkBufferCreateInfo buffer;
    VkMemoryRequirements req;
    VkMemoryAllocateInfo info;
    VkBuffer made;
    memset(&buffer, 0, sizeof buffer);
    buffer.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    buffer.size = size;
    buffer.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    buffer.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(g_device, &buffer, NULL, &made));
    vkGetBufferMemoryRequirements(g_device, made, &req);
    memset(&info, 0, sizeof info);
    info.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    info.allocationSize = req.size;
    info.memoryTypeIndex = memory_type(
        req.memoryTypeBits,
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    VK_CHECK(vkAllocateMemory(g_device, &info, NULL, memory));
    VK_CHECK(vkBindBufferMemory(g_device, made, *memory, 0));
    VK_CHECK(vkMapMemory(g_device, *memory, 0, VK_WHOLE_SIZE, 0, mapped));
    return made;
}

void barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
             VkImageLayout to, VkPipelineStageFlags src_stage, VkAccessFlags src,
             VkPipelineStageFlags dst_stage, VkAccessFlags dst) {
    VkImageMemoryBarrier b;
    memset(&b, 0, sizeof b);
    b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    b.srcAccessMask = src;
    b.dstAccessMask = dst;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange.aspectMask = aspect;
    b.subresourceRange.levelCount = 1;
    b.subresourceRange.layerCount = 1;
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, NULL, 0, NULL, 1, &b);
}

VkBufferImageCopy region(VkImageAspectFlags aspect, VkDeviceSize offset, uint32_t width,
                         uint32_t height) {
    VkBufferImageCopy r;
    memset(&r, 0, sizeof r);
    r.bufferOffset = offset;
    r.imageSubresource.aspectMask = aspect;
    r.imageSubresource.layerCount = 1;
    r.imageExtent.width = width;
    r.imageExtent.height = height;
    r.imageExtent.depth = 1;
    return r;
}

translucid_host_device_create_info host_device_info(void) {
    static const char *none[1];
    translucid_host_device_create_info hd;
    memset(&hd, 0, sizeof hd);
    hd.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_DEVICE_CREATE_INFO;
    hd.api_version = VK_API_VERSION_1_2;
    hd.instance = g_instance;
    hd.physical_device = g_physical;
    hd.device = g_device;
    hd.queue_family_index = g_family;
    hd.get_instance_proc_addr = vkGetInstanceProcAddr;
    hd.enabled_features = &g_features;
    hd.enabled_extension_count = 0;
    hd.enabled_extensions = none;
    return hd;
}


void begin_commands(VkCommandBuffer cmd) {
    VkCommandBufferBeginInfo info;
    memset(&info, 0, sizeof info);
    info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkResetCommandBuffer(cmd, 0));
    VK_CHECK(vkBeginCommandBuffer(cmd, &info));
}

void submit_commands(VkCommandBuffer cmd, VkFence fence) {
    VkSubmitInfo submit;
    VK_CHECK(vkEndCommandBuffer(cmd));
    memset(&submit, 0, sizeof submit);
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    VK_CHECK(vkQueueSubmit(g_queue, 1, &submit, fence));
}

void wait_fence(VkFence fence) {
    VK_CHECK(vkWaitForFences(g_device, 1, &fence, VK_TRUE, UINT64_MAX));
    VK_CHECK(vkResetFences(g_device, 1, &fence));
}

const float g_test_quads[TEST_QUADS][12] = {
    {-1.2f, -0.9f, -2.0f, 0.4f, -0.9f, -2.0f, 0.4f, 0.6f, -2.0f, -1.2f, 0.6f, -2.0f},
    {-0.6f, -0.5f, -3.0f, 1.4f, -0.5f, -3.0f, 1.4f, 1.0f, -3.0f, -0.6f, 1.0f, -3.0f},
    {-1.5f, -0.2f, -1.6f, 1.5f, -0.2f, -3.6f, 1.5f, 0.3f, -3.6f, -1.5f, 0.3f, -1.6f},
    {-0.3f, -1.0f, -2.5f, 0.3f, -1.0f, -2.5f, 0.3f, 1.0f, -2.5f, -0.3f, 1.0f, -2.5f},
};

void make_quad(translucid_context *ctx, size_t i, uint32_t material_flags,
               translucid_mesh *mesh, translucid_material *material, translucid_draw *draw) {
    static const float colours[TEST_QUADS][4] = {{1.0f, 0.1f, 0.1f, 0.5f},
                                                 {0.1f, 0.3f, 1.0f, 0.7f},
                                                 {0.2f, 1.0f, 0.3f, 0.6f},
                                                 {1.0f, 1.0f, 0.2f, 0.4f}};
    static const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
    translucid_mesh_create_info mesh_info;
    translucid_material_create_info material_info;
    memset(&mesh_info, 0, sizeof mesh_info);
    mesh_info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    mesh_info.primitive = TRANSLUCID_PRIMITIVE_TRIANGLES;
    mesh_info.vertex_count = 4;
    mesh_info.positions = g_test_quads[i];
    mesh_info.index_count = 6;
    mesh_info.indices = triangles;
    CHECK(ctx, translucid_mesh_create(ctx, &mesh_info, mesh));
    memset(&material_info, 0, sizeof material_info);
    material_info.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
    memcpy(material_info.base_colour, colours[i], sizeof colours[i]);
    material_info.flags = material_flags;
    CHECK(ctx, translucid_material_create(ctx, &material_info, material));
    memset(draw, 0, sizeof *draw);
    draw->mesh = *mesh;
    draw->material = *material;
    draw->layer = TRANSLUCID_LAYER_TRANSPARENT;
    draw->transform[0] = draw->transform[5] = draw->transform[10] = draw->transform[15] = 1.0f;
}

void render_standalone(translucid_context *ctx, translucid_frame_info info, const uint8_t *colour,
                       const float *depth, uint8_t *out, size_t size) {
    translucid_opaque_layer layer;
    translucid_frame frame;
    memset(&layer, 0, sizeof layer);
    layer.s_type = TRANSLUCID_STRUCTURE_TYPE_OPAQUE_LAYER;
    layer.colour_format = TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB;
    layer.colour = colour;
    layer.depth = depth;
    info.opaque_layer = &layer;
    CHECK(ctx, translucid_frame_render(ctx, &info, &frame));
    CHECK(ctx, translucid_frame_read(ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, out, size));
    CHECK(ctx, translucid_frame_destroy(ctx, frame));
}

void fill_opaque_layer(uint8_t *colour, float *depth, size_t width, size_t height,
                       const float bands[3]) {
    size_t x, y;
    for (y = 0; y < height; y++) {
        for (x = 0; x < width; x++) {
            size_t i = y * width + x;
            colour[i * 4 + 0] = (uint8_t)(40 + 3 * x);
            colour[i * 4 + 1] = (uint8_t)(200 - 3 * y);
            colour[i * 4 + 2] = 90;
            colour[i * 4 + 3] = 255;
            depth[i] = x < width / 4 ? bands[0] : x < width / 2 ? bands[1] : bands[2];
        }
    }
}

void destroy_engine(void) {
    vkDestroyDevice(g_device, NULL);
    if (g_messenger != VK_NULL_HANDLE) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                g_instance, "vkDestroyDebugUtilsMessengerEXT");
        destroy(g_instance, g_messenger, NULL);
    }
    vkDestroyInstance(g_instance, NULL);
}
