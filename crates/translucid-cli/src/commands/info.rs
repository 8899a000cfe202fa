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
        // The bin rasters' tiles: one subgroup's pixels where pipelines can be held to whole
        // subgroups, which a probe checks when a device is made (docs/gpu.md).
        let tile_rows = 1 << translucid::methods::bins::features::tile_shift((&d).into());
        println!(
            "    bin tiles                {}",
            if d.full_subgroups {
                format!(
                    "8x{tile_rows}, if a probe finds whole subgroups of {} lanes",
                    d.subgroup_size
                )
            } else {
                "8x1 (no subgroup size control)".to_string()
            }
        );
        // The variants it gets (docs/gpu.md); TRANSLUCID_PROFILE forces another when rendering.
        let forced = translucid::gpu::Profile::from_env()?;
        println!(
            "    profile                  {}{}",
            d.profile.name(),
            forced.map_or(String::new(), |p| format!(
                " (TRANSLUCID_PROFILE: {} when rendering)",
                p.name()
            ))
        );
        println!(
            "    loop budget              {} iterations a dispatch",
            d.loop_budget
        );
        // How the bin rasters' walks load (docs/gpu.md): storage buffers on GPUs while the
        // records fit one binding.
        let gpu_profile = forced.unwrap_or(d.profile) == translucid::gpu::Profile::Gpu;
        let texels_forced = translucid::methods::bins::features::texel_walk_forced()?;
        println!(
            "    walk loads               {}",
            if translucid::methods::bins::features::storage_walk(gpu_profile, false, texels_forced)
            {
                "storage buffers (texels past one binding)"
            } else {
                "texels"
            }
        );
        // How binning counts (docs/gpu.md): a shared-memory tally per workgroup on GPUs.
        let global_forced = translucid::methods::bins::features::global_counts_forced()?;
        println!(
            "    bin counts               {}",
            match translucid::methods::bins::features::bin_tally_bits(gpu_profile, global_forced) {
                0 => "an atomic an entry".to_string(),
                bits => format!("a workgroup's tally of {} slots", 1 << bits),
            }
        );
        // How the bin rasters sample textures (docs/textures.md).
        let software = d.software_sampling || translucid::gpu::software_sampling_asked()?;
        let slots = translucid::interface::bins::TEXTURE_ARRAY_SLOTS;
        println!(
            "    texture sampling         {}",
            if !gpu_profile || software {
                "software (bit for bit the reference)".to_string()
            } else if d.max_stage_samplers <= slots {
                format!("software (a stage binds {} samplers)", d.max_stage_samplers)
            } else {
                format!("hardware (frames using the first {slots} textures)")
            }
        );
        // The wavelet storage the profile rendering takes picks (docs/gpu.md), and whether
        // the coefficient images take the reference's depth there (a geometry stage).
        let storage =
            translucid::methods::wavelet::Storage::for_profile(forced.unwrap_or(d.profile));
        println!(
            "    wavelet storage          {} (--storage overrides; images {})",
            storage.name(),
            if d.geometry_shader {
                "match the CPU model"
            } else {
                "take the driver's depth: no geometry stage"
            }
        );
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
        let yes = |on: bool| if on { "yes" } else { "no" };
        println!("    dual-source blending     {}", yes(d.dual_source_blend));
        // What the exact peers need.
        println!(
            "    linked_list features     {} (fragmentStoresAndAtomics, geometryShader)",
            yes(d.fragment_stores_and_atomics && d.geometry_shader)
        );
        println!(
            "    independent blending     {} (depth_peeling)",
            yes(d.independent_blend)
        );
    }
    Ok(())
}
