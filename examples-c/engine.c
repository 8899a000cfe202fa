/* A small Vulkan engine for translucid's host-device mode: see engine.h. */
#include "engine.h"

int g_validation_messages = 0;
VkInstance g_instance;
VkPhysicalDevice g_physical;
VkDevice g_device;
VkQueue g_queue;
uint32_t g_family;
VkPhysicalDeviceFeatures g_features;
VkBool32 g_subgroup_size_control;
static VkDebugUtilsMessengerEXT g_messenger;

void engine_fail(const char *what, const char *file, int line) {
    printf("FAIL %s:%d: %s\n", file, line, what);
    exit(1);
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
    app.pApplicationName = "translucid example engine";
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
        if (create == NULL) {
            engine_fail("vkCreateDebugUtilsMessengerEXT not found", __FILE__, __LINE__);
        }
        VK_CHECK(create(g_instance, &messenger, NULL, &g_messenger));
    }
}

/* Whether `device` has every feature `wanted` asks for. */
static int has_features(VkPhysicalDevice device, const VkPhysicalDeviceFeatures *wanted) {
    VkPhysicalDeviceFeatures supported;
    const VkBool32 *want = (const VkBool32 *)wanted, *have = (const VkBool32 *)&supported;
    size_t i;
    vkGetPhysicalDeviceFeatures(device, &supported);
    for (i = 0; i < sizeof supported / sizeof(VkBool32); i++) {
        if (want[i] == VK_TRUE && have[i] != VK_TRUE) return 0;
    }
    return 1;
}

/* Whether `device`'s subgroups are what `wanted` asks for (NULL: anything). */
static int has_subgroups(VkPhysicalDevice device,
                         const translucid_host_subgroup_requirements *wanted) {
    VkPhysicalDeviceSubgroupProperties subgroups;
    VkPhysicalDeviceProperties2 properties;
    if (wanted == NULL) return 1;
    memset(&subgroups, 0, sizeof subgroups);
    subgroups.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
    memset(&properties, 0, sizeof properties);
    properties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    properties.pNext = &subgroups;
    vkGetPhysicalDeviceProperties2(device, &properties);
    return (subgroups.supportedStages & wanted->stages) == wanted->stages &&
           (subgroups.supportedOperations & wanted->operations) == wanted->operations &&
           subgroups.subgroupSize >= wanted->min_size;
}

/* Whether `device` has subgroup size control for compute (the extension and both features),
 * which translucid recommends enabling. */
static int has_subgroup_size_control(VkPhysicalDevice device) {
    VkExtensionProperties *extensions;
    uint32_t count = 0, i;
    int listed = 0;
    VkPhysicalDeviceSubgroupSizeControlFeaturesEXT size;
    VkPhysicalDeviceFeatures2 features;
    VK_CHECK(vkEnumerateDeviceExtensionProperties(device, NULL, &count, NULL));
    extensions = (VkExtensionProperties *)calloc(count + 1, sizeof *extensions);
    if (extensions == NULL) engine_fail("out of memory", __FILE__, __LINE__);
    VK_CHECK(vkEnumerateDeviceExtensionProperties(device, NULL, &count, extensions));
    for (i = 0; i < count; i++) {
        listed |= strcmp(extensions[i].extensionName,
                         VK_EXT_SUBGROUP_SIZE_CONTROL_EXTENSION_NAME) == 0;
    }
    free(extensions);
    /* Its features are only asked of a device that lists it. */
    if (!listed) return 0;
    memset(&size, 0, sizeof size);
    size.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_SIZE_CONTROL_FEATURES_EXT;
    memset(&features, 0, sizeof features);
    features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    features.pNext = &size;
    vkGetPhysicalDeviceFeatures2(device, &features);
    return size.subgroupSizeControl && size.computeFullSubgroups;
}

/* The subgroup requirements chained to `req`, or NULL. */
static const translucid_host_subgroup_requirements *
subgroup_requirements(const translucid_host_requirements *req) {
    const translucid_host_subgroup_requirements *next =
        (const translucid_host_subgroup_requirements *)req->next;
    return next != NULL && next->s_type == TRANSLUCID_STRUCTURE_TYPE_HOST_SUBGROUP_REQUIREMENTS
               ? next
               : NULL;
}

void create_device(const translucid_host_requirements *req) {
    VkPhysicalDevice devices[8];
    uint32_t count = 8, i, d;
    VkQueueFamilyProperties families[16];
    uint32_t family_count;
    VkPhysicalDeviceProperties properties;
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue;
    VkDeviceCreateInfo info;
    VkPhysicalDeviceSubgroupSizeControlFeaturesEXT size_control;
    const char *extensions[8];
    VkResult r = vkEnumeratePhysicalDevices(g_instance, &count, devices);

    if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || count == 0) {
        engine_fail("no Vulkan device", __FILE__, __LINE__);
    }
    g_physical = VK_NULL_HANDLE;
    for (d = 0; d < count && g_physical == VK_NULL_HANDLE; d++) {
        vkGetPhysicalDeviceProperties(devices[d], &properties);
        if (properties.apiVersion < req->api_version ||
            !has_features(devices[d], &req->features) ||
            !has_subgroups(devices[d], subgroup_requirements(req))) {
            continue;
        }
        family_count = 16;
        vkGetPhysicalDeviceQueueFamilyProperties(devices[d], &family_count, families);
        for (i = 0; i < family_count; i++) {
            if ((families[i].queueFlags & req->queue_flags) == req->queue_flags &&
                families[i].timestampValidBits > 0) {
                g_physical = devices[d];
                g_family = i;
                break;
            }
        }
    }
    if (g_physical == VK_NULL_HANDLE) {
        engine_fail("no Vulkan device meets translucid's requirements", __FILE__, __LINE__);
    }

    /* An engine ORs the requirements into its own features; this one has none of its own. */
    g_features = req->features;
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
    if (req->extension_count >= 8) engine_fail("too many extensions", __FILE__, __LINE__);
    for (i = 0; i < req->extension_count; i++) extensions[i] = req->extensions[i];
    info.enabledExtensionCount = req->extension_count;
    /* Recommended where the device has it: translucid's rasters then hold their workgroups
     * to whole subgroups (host_device_info tells it so). */
    g_subgroup_size_control = has_subgroup_size_control(g_physical) ? VK_TRUE : VK_FALSE;
    if (g_subgroup_size_control) {
        memset(&size_control, 0, sizeof size_control);
        size_control.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_SIZE_CONTROL_FEATURES_EXT;
        size_control.subgroupSizeControl = VK_TRUE;
        size_control.computeFullSubgroups = VK_TRUE;
        info.pNext = &size_control;
        extensions[info.enabledExtensionCount++] = VK_EXT_SUBGROUP_SIZE_CONTROL_EXTENSION_NAME;
    }
    info.ppEnabledExtensionNames = extensions;
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
    engine_fail("no suitable memory type", __FILE__, __LINE__);
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
    return create_image_layers(format, usage, width, height, 1);
}

VkImage create_image_layers(VkFormat format, VkImageUsageFlags usage, uint32_t width,
                            uint32_t height, uint32_t layers) {
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
    info.arrayLayers = layers;
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

void every_layer(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                 VkImageLayout from, VkImageLayout to) {
    VkImageMemoryBarrier b;
    memset(&b, 0, sizeof b);
    b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    b.srcAccessMask = b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange.aspectMask = aspect;
    b.subresourceRange.levelCount = 1;
    b.subresourceRange.layerCount = VK_REMAINING_ARRAY_LAYERS;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL, 0, NULL, 1, &b);
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
    static const char *size_extension[1] = {VK_EXT_SUBGROUP_SIZE_CONTROL_EXTENSION_NAME};
    static translucid_host_subgroup_size_control size_control;
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
    hd.enabled_extension_count = g_subgroup_size_control ? 1 : 0;
    hd.enabled_extensions = size_extension;
    if (g_subgroup_size_control) {
        memset(&size_control, 0, sizeof size_control);
        size_control.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_SUBGROUP_SIZE_CONTROL;
        size_control.enabled = VK_TRUE;
        hd.next = &size_control;
    }
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
