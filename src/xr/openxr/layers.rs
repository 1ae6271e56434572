//! The composition layers a frame ends with: one projection layer whose two views are the
//! layers of the colour swapchain, posed where they were rendered from, with the depth
//! swapchain's layers chained (`XR_KHR_composition_layer_depth`) when depth is submitted, then
//! the control panel's quad when it is open, with the compositor's filtering asked for
//! (`XR_FB_composition_layer_settings`: Meta's advice for text, which would shimmer where
//! the compositor minifies it and blur where it magnifies); or no layer when the frame was not
//! rendered.

use ash::vk;
use openxr as xr;

use super::panel::QuadLayer;
use super::session::Session;

/// `xrEndFrame` for a frame displayed at `time`: with the projection layer of `views` when
/// `rendered`, with no layer otherwise. `area` is the part of each image drawn: all of it, or
/// the GPU-time governor's scaled rectangle; the field of view is the same either way (the
/// compositor stretches the rectangle over it). `quad`, the open panel, goes over it, filtered
/// as `panel_filter` asks ([`panel_filter`]).
pub(super) fn end_frame(
    session: &mut Session,
    time: xr::Time,
    views: &[xr::View; 2],
    area: vk::Rect2D,
    rendered: bool,
    quad: Option<QuadLayer<'_>>,
    panel_filter: Option<xr::sys::CompositionLayerSettingsFlagsFB>,
) -> Result<(), xr::sys::Result> {
    if !rendered {
        return session
            .stream
            .end(time, xr::EnvironmentBlendMode::OPAQUE, &[]);
    }
    let rect = xr::Rect2Di {
        offset: xr::Offset2Di {
            x: area.offset.x,
            y: area.offset.y,
        },
        extent: xr::Extent2Di {
            width: area.extent.width as i32,
            height: area.extent.height as i32,
        },
    };
    // Reversed-Z with an infinite far plane: depth 0 is infinitely far, 1 is the near plane.
    let depth_info = session.depth.as_ref().map(|d| {
        [0u32, 1].map(|layer| xr::sys::CompositionLayerDepthInfoKHR {
            ty: xr::sys::CompositionLayerDepthInfoKHR::TYPE,
            next: std::ptr::null(),
            sub_image: xr::sys::SwapchainSubImage {
                swapchain: d.handle.as_raw(),
                image_rect: rect,
                image_array_index: layer,
            },
            min_depth: 0.0,
            max_depth: 1.0,
            near_z: f32::INFINITY,
            far_z: crate::render::camera::NEAR,
        })
    });
    let projection_views = [0usize, 1].map(|i| {
        let v = xr::CompositionLayerProjectionView::new()
            .pose(views[i].pose)
            .fov(views[i].fov)
            .sub_image(
                xr::SwapchainSubImage::new()
                    .swapchain(&session.colour.handle)
                    .image_array_index(i as u32)
                    .image_rect(rect),
            );
        let mut raw = v.into_raw();
        if let Some(d) = depth_info.as_ref() {
            raw.next = &d[i] as *const _ as *const std::ffi::c_void;
        }
        // SAFETY: `raw` came from a valid view; `next` points at a depth info that lives until
        // `end` below returns.
        unsafe { xr::CompositionLayerProjectionView::from_raw(raw) }
    });
    let layer = xr::CompositionLayerProjection::new()
        .space(&session.space)
        .views(&projection_views);
    let Some(q) = quad else {
        return session
            .stream
            .end(time, xr::EnvironmentBlendMode::OPAQUE, &[&layer]);
    };
    let c = q.quad.centre;
    let o = q.quad.orientation;
    let panel = xr::CompositionLayerQuad::new()
        .space(&session.space)
        .eye_visibility(xr::EyeVisibility::BOTH)
        .sub_image(
            xr::SwapchainSubImage::new()
                .swapchain(q.swapchain)
                .image_array_index(0)
                .image_rect(xr::Rect2Di {
                    offset: xr::Offset2Di { x: 0, y: 0 },
                    extent: xr::Extent2Di {
                        width: q.extent.width as i32,
                        height: q.extent.height as i32,
                    },
                }),
        )
        .pose(xr::Posef {
            orientation: xr::Quaternionf {
                x: o.x,
                y: o.y,
                z: o.z,
                w: o.w,
            },
            position: xr::Vector3f {
                x: c.x,
                y: c.y,
                z: c.z,
            },
        })
        .size(xr::Extent2Df {
            width: q.quad.size[0],
            height: q.quad.size[1],
        });
    let settings = panel_filter.map(|flags| xr::sys::CompositionLayerSettingsFB {
        ty: xr::sys::CompositionLayerSettingsFB::TYPE,
        next: std::ptr::null(),
        layer_flags: flags,
    });
    let mut raw = panel.into_raw();
    if let Some(s) = settings.as_ref() {
        raw.next = s as *const _ as *const std::ffi::c_void;
    }
    // SAFETY: `raw` came from a valid quad layer; `next` points at a layer-settings struct
    // that lives until `end` below returns.
    let panel = unsafe { xr::CompositionLayerQuad::from_raw(raw) };
    session
        .stream
        .end(time, xr::EnvironmentBlendMode::OPAQUE, &[&layer, &panel])
}

/// The panel's filtering: supersampling (no shimmer where the compositor minifies its text)
/// and sharpening (no blur where it magnifies), the normal, cheaper kind of each; with
/// `XR_META_automatic_layer_filter` the compositor applies them only where they help. `None`
/// without `XR_FB_composition_layer_settings`.
pub(super) fn panel_filter(
    enabled: &xr::InstanceExtensions,
) -> Option<xr::sys::CompositionLayerSettingsFlagsFB> {
    filter_for(
        enabled.fb_composition_layer_settings.is_some(),
        enabled.meta_automatic_layer_filter.is_some(),
    )
}

/// [`panel_filter`] from whether each extension is enabled.
fn filter_for(settings: bool, automatic: bool) -> Option<xr::sys::CompositionLayerSettingsFlagsFB> {
    type F = xr::sys::CompositionLayerSettingsFlagsFB;
    settings.then(|| {
        let both = F::NORMAL_SUPER_SAMPLING | F::NORMAL_SHARPENING;
        if automatic {
            both | F::AUTO_LAYER_FILTER
        } else {
            both
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_panel_is_filtered_only_where_the_runtime_can() {
        type F = xr::sys::CompositionLayerSettingsFlagsFB;
        assert_eq!(filter_for(false, false), None);
        let f = filter_for(true, false).unwrap();
        assert!(f.contains(F::NORMAL_SUPER_SAMPLING) && f.contains(F::NORMAL_SHARPENING));
        assert!(!f.contains(F::AUTO_LAYER_FILTER));
        // Automatic filtering must not be the only bit (the extension's valid usage).
        let auto = filter_for(true, true).unwrap();
        assert!(auto.contains(F::AUTO_LAYER_FILTER | F::NORMAL_SHARPENING));
    }
}
