//! The control panel painted on the GPU (issue 31): egui's triangles through
//! `render::panel::PanelPainter` into an image of the panel's size, read back. Checks: zero
//! validation messages, the panel's background where nothing is drawn, text that stands out
//! from it, a click on a Beaufort preset changing what is drawn, and nothing leaked. Writes
//! `target/panel.png` (`docs/panel/panel.png` in the README is this image).

use crate::common;

use ash::vk;
use vr_ocean::render::barrier::{self, Access, GlobalBarrier};
use vr_ocean::render::memory::{Buffer, Image, ImageDesc};
use vr_ocean::render::panel::{PanelFrame, PanelPainter, PanelTarget};
use vr_ocean::render::GpuContext;
use vr_ocean::ui::panel::{Comfort, Panel, PanelModel, Perf, PointerEvent};
use vr_ocean::ui::Beaufort;

/// Image pixels per egui point: the quad layer's density (see the README's pixels per degree).
const PPP: f32 = 2.5;

fn model() -> PanelModel {
    PanelModel {
        wind_speed: Beaufort::new(4).unwrap().wind_speed(),
        wind_direction_deg: 45.0,
        sun_elevation_deg: 30.0,
        sun_azimuth_deg: 150.0,
        clouds: 0.3,
        bodies: 4,
        comfort: Comfort::default(),
        in_water: false,
        perf: Perf {
            frame_ms: 11.1,
            gpu_ms: Some(7.9),
            level: Some("full"),
        },
    }
}

/// Paints the panel's latest image into `target` and reads it back as RGBA8 rows.
fn paint(
    ctx: &GpuContext,
    painter: &mut PanelPainter,
    panel: &mut Panel,
    target: &Image,
    readback: &Buffer,
) -> Vec<u8> {
    let textures = panel.take_textures();
    let mut result = Ok(());
    vr_ocean::render::one_shot(ctx, |cmd| {
        result = painter.record(
            ctx,
            cmd,
            PanelFrame {
                view: target.view,
                extent: target.extent,
                primitives: panel.primitives(),
                textures: &textures,
                pixels_per_point: panel.pixels_per_point(),
            },
        );
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: target.extent.width,
                height: target.extent.height,
                depth: 1,
            },
        };
        // SAFETY: the pass left the image in TRANSFER_SRC_OPTIMAL (its target's `then`) with
        // its writes made available to transfers; the buffer holds the whole image.
        unsafe {
            ctx.device.cmd_copy_image_to_buffer(
                cmd,
                target.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.raw,
                &[region],
            );
        }
        barrier::record::<0>(
            &ctx.device,
            cmd,
            [],
            Some(GlobalBarrier {
                from: Access::TransferWrite,
                to: Access::HostRead,
            }),
        );
    })
    .unwrap();
    result.unwrap();
    readback.bytes().to_vec()
}

fn luma(p: &[u8]) -> f32 {
    0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32
}

#[test]
fn the_panel_paints_its_text_and_follows_a_click() {
    let ctx = GpuContext::new(&common::gpu::validated()).expect("a Vulkan device (lavapipe)");
    let mut panel = Panel::new(true, PPP);
    let mut m = model();
    assert!(panel.update(&m, 0.0).redrawn);
    let [w, h] = panel.size_px();
    let extent = vk::Extent2D {
        width: w,
        height: h,
    };
    let mut target = Image::new(
        &ctx,
        ImageDesc {
            format: vk::Format::R8G8B8A8_UNORM,
            extent,
            layers: 1,
            mips: 1,
            samples: vk::SampleCountFlags::TYPE_1,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            aspect: vk::ImageAspectFlags::COLOR,
            transient: false,
        },
    )
    .unwrap();
    let mut readback = Buffer::new(
        &ctx,
        4 * w as u64 * h as u64,
        vk::BufferUsageFlags::TRANSFER_DST,
        true,
    )
    .unwrap();
    let mut painter = PanelPainter::new(
        &ctx,
        PanelTarget {
            format: vk::Format::R8G8B8A8_UNORM,
            then: Access::TransferRead,
        },
    )
    .unwrap();
    let first = paint(&ctx, &mut painter, &mut panel, &target, &readback);
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .unwrap()
        .join("panel.png");
    image::save_buffer(&out, &first, w, h, image::ColorType::Rgba8).unwrap();
    println!("wrote {} ({w}x{h})", out.display());

    // The background: egui's panel fill, opaque, where nothing is drawn (bottom-right corner).
    let px = |img: &[u8], x: u32, y: u32| {
        let i = 4 * (y * w + x) as usize;
        [img[i], img[i + 1], img[i + 2], img[i + 3]]
    };
    assert_eq!(px(&first, w - 3, h - 3), [18, 28, 38, 255]);
    // Text: the heading's band holds bright glyph pixels against the dark fill, with the
    // intermediate coverage of anti-aliased edges.
    let band = |img: &[u8], y0: u32, y1: u32| {
        let (mut bright, mut edge) = (0, 0);
        for y in y0..y1 {
            for x in 0..w / 2 {
                let l = luma(&px(img, x, y));
                if l > 170.0 {
                    bright += 1;
                } else if l > 60.0 {
                    edge += 1;
                }
            }
        }
        (bright, edge)
    };
    let (bright, edge) = band(&first, 0, (40.0 * PPP) as u32);
    println!("heading band: {bright} bright glyph pixels, {edge} edge pixels");
    assert!(bright > 300 && edge > 100, "{bright} bright, {edge} edge");

    // Click Beaufort 8: the redraw differs where the sea state is shown, not at the bottom.
    let eight = panel.widgets().beaufort[8];
    let at = [(eight[0] + eight[2]) / 2.0, (eight[1] + eight[3]) / 2.0];
    for (t, e) in [
        (0.1, PointerEvent::Aim(Some(at))),
        (0.2, PointerEvent::Trigger(true)),
        (0.3, PointerEvent::Trigger(false)),
    ] {
        panel.handle(e);
        let u = panel.update(&m, t);
        if let Some(edited) = u.edited {
            m = edited;
        }
    }
    assert_eq!(m.beaufort(), Beaufort::new(8).ok());
    panel.update(&m, 0.4);
    let second = paint(&ctx, &mut painter, &mut panel, &target, &readback);
    let differs = |y0: u32, y1: u32| {
        (y0..y1)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| px(&first, x, y) != px(&second, x, y))
            .count()
    };
    let sea_rows = (eight[1] as u32 - 40)..(eight[3] as u32 + 120);
    let changed = differs(sea_rows.start, sea_rows.end);
    println!("after the click: {changed} pixels changed in the sea rows");
    assert!(changed > 200, "{changed}");
    let perf = panel.widgets().perf;
    assert!(
        perf[1] > sea_rows.end as f32,
        "the perf line is below the sea rows: {perf:?}"
    );
    assert_eq!(
        differs(perf[1] as u32, perf[3] as u32 + 1),
        0,
        "the perf line did not change"
    );

    ctx.wait_idle();
    painter.destroy(&ctx);
    readback.destroy(&ctx);
    target.destroy(&ctx);
    assert_eq!(
        ctx.validation_errors(),
        0,
        "validation errors: {:?}",
        ctx.validation.as_ref().map(|v| v.messages())
    );
}
