//! Structure types: the `s_type` every extensible struct starts with, so that a zeroed, garbage
//! or wrong struct is caught instead of misread, and so that later versions can chain new
//! structures through `next` without changing any existing layout.

/// Values of the `s_type` field. 0 is never valid, so a zeroed struct is always rejected.
/// Each value is named after the struct it tags: `translucid_foo_bar` takes
/// `TRANSLUCID_STRUCTURE_TYPE_FOO_BAR`.
#[allow(non_camel_case_types)]
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum translucid_structure_type {
    ContextCreateInfo = 1,
    MeshCreateInfo = 2,
    TextureCreateInfo = 3,
    MaterialCreateInfo = 4,
    FrameInfo = 5,
    OpaqueLayer = 6,
    FrameStatistics = 7,
    /// `translucid_sampler_info`, chained to the texture create-info.
    SamplerInfo = 8,
    /// Method settings, chained to the frame info.
    ExactSettings = 9,
    WaveletSettings = 10,
    LinkedListSettings = 11,
    DepthPeelingSettings = 12,
    /// `translucid_prepare_info`.
    PrepareInfo = 13,
    /// `translucid_memory_statistics`.
    MemoryStatistics = 14,
    /// `translucid_memory_create_info`, chained to the context create-info.
    MemoryCreateInfo = 15,
    /// `translucid_host_device_create_info`, chained to the context create-info.
    HostDeviceCreateInfo = 100,
    /// `translucid_host_requirements`.
    HostRequirements = 101,
    /// `translucid_host_frame_targets`.
    HostFrameTargets = 102,
    /// `translucid_host_subgroup_requirements`, chained to the requirements.
    HostSubgroupRequirements = 103,
    /// `translucid_host_subgroup_size_control`, chained to the host device create-info.
    HostSubgroupSizeControl = 104,
    /// `translucid_host_image_layers`, chained to the frame targets.
    HostImageLayers = 105,
    /// `translucid_host_image_formats`, chained to the prepare info.
    HostImageFormats = 106,
    /// `translucid_host_image_region`, chained to the frame targets.
    HostImageRegion = 107,
    /// `translucid_host_frame_views`, chained to the frame targets.
    HostFrameViews = 108,
    /// `translucid_host_views_create_info`, chained to the engine's device description.
    HostViewsCreateInfo = 109,
    /// `translucid_frame_view_statistics`, chained to the frame statistics.
    FrameViewStatistics = 110,
}

impl translucid_structure_type {
    const ALL: [Self; 26] = [
        Self::ContextCreateInfo,
        Self::MeshCreateInfo,
        Self::TextureCreateInfo,
        Self::MaterialCreateInfo,
        Self::FrameInfo,
        Self::OpaqueLayer,
        Self::FrameStatistics,
        Self::SamplerInfo,
        Self::ExactSettings,
        Self::WaveletSettings,
        Self::LinkedListSettings,
        Self::DepthPeelingSettings,
        Self::PrepareInfo,
        Self::MemoryStatistics,
        Self::MemoryCreateInfo,
        Self::HostDeviceCreateInfo,
        Self::HostRequirements,
        Self::HostFrameTargets,
        Self::HostSubgroupRequirements,
        Self::HostSubgroupSizeControl,
        Self::HostImageLayers,
        Self::HostImageFormats,
        Self::HostImageRegion,
        Self::HostFrameViews,
        Self::HostViewsCreateInfo,
        Self::FrameViewStatistics,
    ];

    pub fn from_raw(value: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|t| *t as u32 == value)
    }

    /// The value's name in the header, such as `TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO`.
    pub fn c_name(self) -> String {
        crate::cast::c_enum_name("TRANSLUCID_STRUCTURE_TYPE", &format!("{self:?}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_structure_types_as_the_header_does() {
        let header = include_str!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../include/translucid.h"
        ));
        for t in translucid_structure_type::ALL {
            let line = format!("{} = {},", t.c_name(), t as u32);
            assert!(header.contains(&line), "the header lacks {line}");
        }
        let format = crate::cast::c_enum_name("TRANSLUCID_PIXEL_FORMAT", "Rgba32fLinear");
        assert!(header.contains(&format!("{format} = 1,")), "{format}");
    }
}
