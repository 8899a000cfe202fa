use translucid::gpu::list_devices;

pub fn run() -> translucid::Result<()> {
    let devices = list_devices()?;
    if devices.is_empty() {
        println!("no Vulkan 1.2 device found");
    }
    for d in devices {
        println!(
            "[{}] {} ({}, Vulkan {}, {})",
            d.index, d.name, d.kind, d.api_version, d.driver
        );
        println!("    subgroup size            {}", d.subgroup_size);
        println!(
            "    shared memory            {} KB",
            d.max_shared_memory / 1024
        );
        println!(
            "    storage buffer range     {} MB",
            d.max_storage_buffer_range / (1024 * 1024)
        );
        println!(
            "    workgroup invocations    {}",
            d.max_compute_workgroup_invocations
        );
        println!("    largest image            {}", d.max_image_dimension_2d);
        println!("    timestamp period         {} ns", d.timestamp_period_ns);
        println!(
            "    dual-source blending     {}",
            if d.dual_source_blend { "yes" } else { "no" }
        );
    }
    Ok(())
}
