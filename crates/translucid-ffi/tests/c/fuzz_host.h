/*
 * The engine's side of the C API fuzzer's host-device mode (fuzz_calls --host-device, over
 * examples-c/engine.c): one Vulkan device made with every method's requirements, shared by the
 * fuzzer's threads, and engine frames recorded around translucid_frame_record.
 */
#ifndef TRANSLUCID_FUZZ_HOST_H
#define TRANSLUCID_FUZZ_HOST_H

#include <stdint.h>

#include "translucid.h"

/* Creates the instance and device (with validation when TRANSLUCID_VALIDATION=1). */
void fuzz_host_start(void);
/* Destroys them; returns the validation errors reported since the start. */
int fuzz_host_stop(void);
/* Destroys the calling thread's command buffer and readback buffer, if it made them. */
void fuzz_host_thread_end(void);
/* What a host-device context's create-info takes as `next`. */
const void *fuzz_host_device_info(void);

/* How an engine frame went past its recording. */
typedef struct {
    /* translucid_frame_complete's result, once the submission finished (-1 when nothing
     * was recorded). */
    translucid_result completed;
    /* Whether the composited colour read back finite (always 1 for UNORM and sRGB images). */
    int finite;
} fuzz_host_outcome;

/* One engine frame of `info` on `ctx`: colour and depth images of random supported formats,
 * sizes (the frame's or larger) and layouts, cleared as an opaque layer; translucid's frame
 * recorded into a command buffer between the engine's own commands, submitted, waited for
 * and completed. `below(n)` draws a number in [0, n). Returns translucid_frame_record's
 * result; a recorded frame's handle is in `*out` (when `out` is not NULL). */
translucid_result fuzz_host_frame(translucid_context *ctx, const translucid_frame_info *info,
                                  translucid_frame *out, uint32_t (*below)(uint32_t),
                                  fuzz_host_outcome *outcome);

#endif
