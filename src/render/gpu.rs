//! Offscreen drawing on the simulation's device (`tumble_gpu::gpu()`, lavapipe in CI): spheres
//! as impostors with their true depth, triangles flat-shaded, translucent ones blended last;
//! the colour target is copied into a buffer and read back as RGBA rows.

use super::camera::Camera;
use glam::DVec3;
use wgpu::util::DeviceExt as _;

/// The WGSL of every picture (validated by naga in this module's tests).
pub const SHADER: &str = include_str!("render.wgsl");
/// The shader's entry points (unique among all of tumble's WGSL modules).
pub const ENTRY_POINTS: [&str; 4] = ["sphere_corner", "sphere_surface", "surface_corner", "surface_fill"];
/// The shader's shading terms (render.wgsl): a surface facing the light shows its colour exactly.
pub const AMBIENT: f32 = 0.35;
pub const DIFFUSE: f32 = 0.65;
/// Towards the light, in view coordinates (right, up, towards the viewer): above left, in front.
pub const LIGHT: [f32; 3] = [-0.3, 0.4, 0.866_025_4];
/// What is left where nothing is drawn.
pub const BACKGROUND: [u8; 4] = [255, 255, 255, 255];

/// A sphere: world centre, radius, colour (sRGB components in [0, 1]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub centre: DVec3,
    pub radius: f64,
    pub colour: [f32; 3],
}

/// A triangle in world coordinates; `alpha` < 1 blends it over what is behind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub corners: [DVec3; 3],
    pub colour: [f32; 3],
    pub alpha: f32,
}

/// A line one pixel wide (a wall's edge), hidden behind what is nearer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub ends: [DVec3; 2],
    pub colour: [f32; 3],
}

/// Everything one image shows.
#[derive(Clone, Debug, Default)]
pub struct Picture {
    pub spheres: Vec<Sphere>,
    pub triangles: Vec<Triangle>,
    pub lines: Vec<Line>,
}

/// A fixed-size offscreen target and the three pipelines that draw into it.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    width: u32,
    height: u32,
    layout: wgpu::BindGroupLayout,
    spheres: wgpu::RenderPipeline,
    opaque: wgpu::RenderPipeline,
    translucent: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    colour: wgpu::Texture,
    depth: wgpu::Texture,
    readback: wgpu::Buffer,
    padded_row: u32,
}

const COLOUR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

impl Renderer {
    /// A renderer of `width` × `height` images on the process's device.
    pub fn new(width: u32, height: u32) -> Result<Renderer, String> {
        let gpu = tumble_gpu::gpu().map_err(|e| e.to_string())?;
        let (device, queue) = (gpu.device.clone(), gpu.queue.clone());
        let most = gpu.limits.max_texture_dimension_2d;
        if width == 0 || height == 0 || width > most || height > most {
            return Err(format!("--size {width}x{height}: each side must be 1 to {most} pixels on {}", gpu.adapter.name));
        }
        let module =
            device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("render"), source: wgpu::ShaderSource::Wgsl(SHADER.into()) });
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
            count: None,
        };
        let read = wgpu::BufferBindingType::Storage { read_only: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("render"),
            entries: &[entry(0, wgpu::BufferBindingType::Uniform), entry(1, read), entry(2, read)],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("render"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |vertex: &str, fragment: &str, topology, depth_write: bool, blend: Option<wgpu::BlendState>| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(fragment),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState { module: &module, entry_point: Some(vertex), compilation_options: Default::default(), buffers: &[] },
                primitive: wgpu::PrimitiveState { topology, cull_mode: None, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState { format: COLOUR_FORMAT, blend, write_mask: wgpu::ColorWrites::ALL })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        let spheres = pipeline("sphere_corner", "sphere_surface", triangles, true, None);
        let opaque = pipeline("surface_corner", "surface_fill", triangles, true, None);
        let translucent = pipeline("surface_corner", "surface_fill", triangles, false, Some(wgpu::BlendState::ALPHA_BLENDING));
        let lines = pipeline("surface_corner", "surface_fill", wgpu::PrimitiveTopology::LineList, false, None);
        let size = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
        let texture = |format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("render target"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let colour = texture(COLOUR_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC);
        let depth = texture(DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let padded_row = (4 * width).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render readback"),
            size: padded_row as u64 * height as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Ok(Renderer { device, queue, width, height, layout, spheres, opaque, translucent, lines, colour, depth, readback, padded_row })
    }

    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Draws `picture` seen by `camera`; returns the image as RGBA rows, top row first.
    pub fn draw(&self, picture: &Picture, camera: &Camera) -> Vec<u8> {
        let f = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
        let mut spheres: Vec<[f32; 4]> = Vec::with_capacity(2 * picture.spheres.len() + 2);
        for s in &picture.spheres {
            let [x, y, z] = f(camera.to_view(s.centre));
            spheres.push([x, y, z, s.radius as f32]);
            spheres.push([s.colour[0], s.colour[1], s.colour[2], 1.0]);
        }
        // Opaque triangles first, translucent ones after (drawn in their own pass, blended).
        let (opaque, translucent): (Vec<&Triangle>, Vec<&Triangle>) = picture.triangles.iter().partition(|t| t.alpha >= 1.0);
        let mut corners: Vec<[f32; 4]> = Vec::with_capacity(9 * picture.triangles.len() + 3);
        for t in opaque.iter().chain(&translucent) {
            let v = t.corners.map(|c| camera.to_view(c));
            let normal = f((v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero());
            for c in v {
                let [x, y, z] = f(c);
                corners.push([x, y, z, 1.0]);
                corners.push([normal[0], normal[1], normal[2], 0.0]);
                corners.push([t.colour[0], t.colour[1], t.colour[2], t.alpha]);
            }
        }
        // Lines are not shaded (normal.w = 1).
        for l in &picture.lines {
            for c in l.ends {
                let [x, y, z] = f(camera.to_view(c));
                corners.push([x, y, z, 1.0]);
                corners.push([0.0, 0.0, 0.0, 1.0]);
                corners.push([l.colour[0], l.colour[1], l.colour[2], 1.0]);
            }
        }
        // A binding may not be empty.
        spheres.resize(spheres.len().max(2), [0.0; 4]);
        corners.resize(corners.len().max(3), [0.0; 4]);
        let view: [[f32; 4]; 2] =
            [[(1.0 / camera.half_width) as f32, (1.0 / camera.half_height) as f32, camera.depth as f32, 0.0], [LIGHT[0], LIGHT[1], LIGHT[2], 0.0]];
        let buffer =
            |label, contents: &[u8], usage| self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
        let view = buffer("render view", bytemuck::cast_slice(&view), wgpu::BufferUsages::UNIFORM);
        let sphere_buffer = buffer("render spheres", bytemuck::cast_slice(&spheres), wgpu::BufferUsages::STORAGE);
        let corner_buffer = buffer("render corners", bytemuck::cast_slice(&corners), wgpu::BufferUsages::STORAGE);
        let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("render"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: view.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: sphere_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: corner_buffer.as_entire_binding() },
            ],
        });
        let colour_view = self.colour.create_view(&Default::default());
        let depth_view = self.depth.create_view(&Default::default());
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("render") });
        {
            let b = BACKGROUND.map(|c| c as f64 / 255.0);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("render"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &colour_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r: b[0], g: b[1], b: b[2], a: b[3] }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &bind, &[]);
            pass.set_pipeline(&self.spheres);
            pass.draw(0..6, 0..picture.spheres.len() as u32);
            let (n_opaque, n_all) = (3 * opaque.len() as u32, 3 * (opaque.len() + translucent.len()) as u32);
            pass.set_pipeline(&self.opaque);
            pass.draw(0..n_opaque, 0..1);
            pass.set_pipeline(&self.translucent);
            pass.draw(n_opaque..n_all, 0..1);
            pass.set_pipeline(&self.lines);
            pass.draw(n_all..n_all + 2 * picture.lines.len() as u32, 0..1);
        }
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo { texture: &self.colour, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(self.padded_row), rows_per_image: Some(self.height) },
            },
            wgpu::Extent3d { width: self.width, height: self.height, depth_or_array_layers: 1 },
        );
        self.queue.submit([encoder.finish()]);
        let slice = self.readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, |r| r.expect("mapping the rendered image"));
        self.device.poll(wgpu::PollType::Wait { submission_index: None, timeout: None }).expect("waiting for the device");
        let mut rgba = Vec::with_capacity(4 * (self.width * self.height) as usize);
        {
            let mapped = slice.get_mapped_range().expect("the mapped image");
            for row in mapped.chunks_exact(self.padded_row as usize) {
                rgba.extend_from_slice(&row[..4 * self.width as usize]);
            }
        }
        self.readback.unmap();
        rgba
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn module() -> naga::Module {
        let module = naga::front::wgsl::parse_str(SHADER).unwrap_or_else(|e| panic!("render.wgsl: {}", e.emit_to_string(SHADER)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("render.wgsl: {}", e.emit_to_string(SHADER)));
        module
    }

    #[test]
    fn the_render_shader_validates_and_its_entry_points_are_unique_among_all_modules() {
        let module = module();
        let names: Vec<&str> = module.entry_points.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names.len(), ENTRY_POINTS.len(), "{names:?}");
        for e in ENTRY_POINTS {
            assert!(names.contains(&e), "render.wgsl has no entry point {e}");
            for m in tumble_gpu::shaders::MODULES.iter().chain([&tumble_gpu::shaders::POLYHEDRA_TEST_MODULE]) {
                assert!(!m.entry_points.contains(&e), "entry point {e} is also module {}'s", m.name);
            }
        }
    }

    #[test]
    fn the_host_and_the_shader_shade_alike() {
        let module = module();
        let constant = |name: &str| {
            let c = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("no constant {name}")).1;
            match module.global_expressions[c.init] {
                naga::Expression::Literal(naga::Literal::F32(v)) => v,
                ref other => panic!("{name} = {other:?}"),
            }
        };
        assert_eq!((constant("AMBIENT"), constant("DIFFUSE")), (AMBIENT, DIFFUSE));
        assert_eq!(AMBIENT + DIFFUSE, 1.0, "a face towards the light shows its colour exactly");
        assert!((LIGHT.iter().map(|v| v * v).sum::<f32>() - 1.0).abs() < 1e-6, "the light direction is a unit vector");
    }
}
