//! The wgpu side: one device ([`Gpu`]), a compiled model ([`Tracer`]: the shader of
//! [`crate::codegen::shader`] with its two entry points, the cell pass and the pixel
//! pass), a frame's rays uploaded once ([`Prepared`]) and run as often as wanted.

use crate::codegen;
use crate::convert;
use crate::GpuArith;
use bytemuck::{Pod, Zeroable};
use model_ir::Tape;
use std::time::{Duration, Instant};
use wgpu::util::DeviceExt;

/// A GPU device and its queue.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
}

impl Gpu {
    /// The first adapter wgpu finds (Vulkan, Metal or DX12; a software Vulkan such as
    /// lavapipe counts). The error says none was found.
    pub fn new() -> Result<Gpu, String> {
        let instance = wgpu::Instance::new(&wgpu::InstanceDescriptor {
            backends: wgpu::Backends::PRIMARY,
            ..Default::default()
        });
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
        }))
        .map_err(|e| format!("no GPU adapter found (Vulkan, Metal or DX12): {e}"))?;
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("tracer-gpu"),
            required_features: wgpu::Features::empty(),
            required_limits: adapter.limits(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| format!("GPU adapter {} refused a device: {e}", info.name))?;
        Ok(Gpu {
            device,
            queue,
            info,
        })
    }

    /// The adapter's name and backend, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)`.
    pub fn name(&self) -> String {
        format!("{} ({:?})", self.info.name, self.info.backend)
    }

    /// Whether the adapter is a CPU implementation (lavapipe, WARP, SwiftShader).
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    fn module(&self, src: &str) -> Result<wgpu::ShaderModule, String> {
        self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let m = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("tracer-gpu"),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            });
        match pollster::block_on(self.device.pop_error_scope()) {
            Some(e) => Err(format!("the generated shader does not compile: {e}")),
            None => Ok(m),
        }
    }

    /// Runs `entry` of `wgsl` over `invocations` (workgroups of 64) with `input` at
    /// binding 1 (read-only storage) and returns binding 2 (`out_words` u32 words). The
    /// shader declares `params` at binding 0 as a uniform `struct { zero: u32, n: u32,
    /// pad0: u32, pad1: u32 }` (`n` = `invocations`). For the arithmetic's tests.
    pub fn compute(
        &self,
        wgsl: &str,
        entry: &str,
        input: &[u32],
        out_words: usize,
        invocations: u32,
    ) -> Result<Vec<u32>, String> {
        let module = self.module(wgsl)?;
        let d = &self.device;
        let uni = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytemuck::cast_slice(&[0u32, invocations, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let inp = storage_init(d, if input.is_empty() { &[0] } else { input }, false);
        let out = d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: (out_words.max(1) * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipe = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: None,
            layout: None,
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(self.device.pop_error_scope()) {
            return Err(format!("the test kernel does not compile: {e}"));
        }
        let bg = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipe.get_bind_group_layout(0),
            entries: &[entry_of(0, &uni), entry_of(1, &inp), entry_of(2, &out)],
        });
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipe);
            pass.set_bind_group(0, &bg, &[]);
            pass.dispatch_workgroups(invocations.div_ceil(64).max(1), 1, 1);
        }
        self.queue.submit([enc.finish()]);
        let words = self.read_u32(&out, out_words)?;
        Ok(words)
    }

    /// Waits for the submitted work. wgpu's wait gives up after a few seconds, which a
    /// software renderer's long frame exceeds: wait again, up to ten minutes in all.
    fn wait(&self) -> Result<(), String> {
        let start = Instant::now();
        loop {
            match self.device.poll(wgpu::PollType::Wait) {
                Ok(_) => return Ok(()),
                Err(wgpu::PollError::Timeout) if start.elapsed() < Duration::from_secs(600) => {}
                Err(e) => return Err(format!("GPU work did not finish: {e}")),
            }
        }
    }

    fn read_u32(&self, buf: &wgpu::Buffer, words: usize) -> Result<Vec<u32>, String> {
        let size = (words.max(1) * 4) as u64;
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(buf, 0, &staging, 0, size);
        self.queue.submit([enc.finish()]);
        let slice = staging.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| format!("GPU read-back lost: {e}"))?
            .map_err(|e| format!("GPU read-back failed: {e}"))?;
        let data = slice.get_mapped_range();
        let mut v: Vec<u32> = bytemuck::cast_slice(&data).to_vec();
        drop(data);
        staging.unmap();
        v.truncate(words);
        Ok(v)
    }
}

fn storage_init(d: &wgpu::Device, words: &[u32], writable: bool) -> wgpu::Buffer {
    let mut usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
    if writable {
        usage |= wgpu::BufferUsages::COPY_SRC;
    }
    d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(words),
        usage,
    })
}

fn entry_of(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: b.as_entire_binding(),
    }
}

/// The shaders' `Params` uniform (layout of `search.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    zero: u32,
    eps_abs: f32,
    eps_rel: f32,
    width: u32,
    height: u32,
    cell: u32,
    cells_x: u32,
    culling: u32,
    pruning: u32,
    max_iter: u32,
    normal_h: f32,
    refine: f32,
}

/// The shaders' `Job`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Job {
    d_mid: [f32; 3],
    s0: f32,
    d_rad: [f32; 3],
    s1: f32,
    o_mid: [f32; 3],
    pad0: f32,
    o_rad: [f32; 3],
    pad1: f32,
}

/// One ray or bundle in `f64`: the points `o + s d` for `s` in `[s0, s1]`, every origin
/// `o` with `|o_k - origin_k| <= origin_rad_k` and every direction `d` with
/// `|d_k - dir_k| <= dir_rad_k`. A pixel's ray has `dir` its unit direction (then `s` is
/// the distance from its origin, the eye of a pinhole or a point of an orthographic
/// view's image plane) and both radii zero; `s0 > s1` for a ray that misses the domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bundle {
    /// Central origin.
    pub origin: [f64; 3],
    /// Radius of the origins, per component (`>= 0`).
    pub origin_rad: [f64; 3],
    /// Central direction.
    pub dir: [f64; 3],
    /// Radius of the directions, per component (`>= 0`).
    pub dir_rad: [f64; 3],
    /// Start of the searched parameter range.
    pub s0: f64,
    /// End of the searched parameter range.
    pub s1: f64,
}

impl Bundle {
    fn to_job(self) -> Job {
        // Each component as an f32 midpoint and a radius holding the f64 value's
        // rounding and the given radius (the sum of two f32 in f64 is exact; rounded up).
        let enclose = |v: [f64; 3], rad: [f64; 3]| {
            let (mut mid, mut r) = ([0.0f32; 3], [0.0f32; 3]);
            for k in 0..3 {
                let (m, e) = convert::coord(v[k]);
                mid[k] = m;
                r[k] = convert::up(e as f64 + convert::up(rad[k].abs()) as f64);
            }
            (mid, r)
        };
        let (d_mid, d_rad) = enclose(self.dir, self.dir_rad);
        let (o_mid, o_rad) = enclose(self.origin, self.origin_rad);
        let finite = self.s0.is_finite() && self.s1.is_finite() && self.s0 <= self.s1;
        let (s0, s1) = if finite && self.s0.abs() < convert::LIM && self.s1.abs() < convert::LIM {
            (convert::down(self.s0), convert::up(self.s1))
        } else {
            (1.0, 0.0)
        };
        Job {
            d_mid,
            s0,
            d_rad,
            s1,
            o_mid,
            pad0: 0.0,
            o_rad,
            pad1: 0.0,
        }
    }
}

/// Screen cells for the culling pass (Section 5.3.2): `cell x cell` pixels each,
/// `cells_x` per row, one [`Bundle`] per cell (row-major) enclosing its pixels' rays
/// over the part of the domain they cross.
#[derive(Clone, Debug, PartialEq)]
pub struct Cells {
    /// Side of a cell in pixels.
    pub cell: u32,
    /// Cells per row.
    pub cells_x: u32,
    /// One bundle per cell.
    pub bundles: Vec<Bundle>,
}

/// What one frame needs: the eye, one [`Bundle`] per pixel (row-major), the precision
/// along the rays, and the cells when culling.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// One bundle per pixel.
    pub rays: Vec<Bundle>,
    /// A segment is resolved once shorter than `eps_abs + eps_rel * s`.
    pub eps_abs: f64,
    /// See `eps_abs`.
    pub eps_rel: f64,
    /// Least step of the normals' central differences.
    pub normal_h: f64,
    /// Argument pruning (no effect for IA).
    pub pruning: bool,
    /// The culling pass, or `None` for none.
    pub cells: Option<Cells>,
}

/// What the search said of a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// No root on the ray (proved).
    Miss,
    /// The first root, proved by a sign change within the precision.
    Hit,
    /// A segment within the precision (or at `f32`'s resolution, or out of iterations)
    /// whose range holds 0, without a proved sign change: a hit that may be spurious.
    Unconfirmed,
    /// The pixel's cell was proved empty by the culling pass.
    Culled,
}

impl Status {
    /// Whether the pixel is drawn as a hit.
    pub fn is_hit(self) -> bool {
        matches!(self, Status::Hit | Status::Unconfirmed)
    }
}

/// A frame's results, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Per pixel.
    pub status: Vec<Status>,
    /// Distance along the ray to the reported root (meaningful for hits).
    pub depth: Vec<f32>,
    /// Unit outward normal `-grad f / |grad f|` at the hit, `[0, 0, 0]` when unknown.
    pub normal: Vec<[f32; 3]>,
    /// Range evaluations per pixel.
    pub evals: Vec<u32>,
    /// Cells proved empty by the culling pass.
    pub cells_culled: u64,
}

/// A model compiled for one arithmetic on one device.
pub struct Tracer<'g> {
    gpu: &'g Gpu,
    arith: GpuArith,
    layout: wgpu::BindGroupLayout,
    px: wgpu::ComputePipeline,
    cell: wgpu::ComputePipeline,
}

/// A frame uploaded to the device, ready to run.
pub struct Prepared {
    width: u32,
    height: u32,
    ncells: u32,
    culling: bool,
    bind: wgpu::BindGroup,
    out_px: wgpu::Buffer,
    out_st: wgpu::Buffer,
    cells: wgpu::Buffer,
}

impl<'g> Tracer<'g> {
    /// Compiles the model `tape` for `arith` (one shader, two pipelines).
    pub fn new(gpu: &'g Gpu, tape: &Tape, arith: GpuArith) -> Result<Tracer<'g>, String> {
        let src = codegen::shader(tape, arith)?;
        let module = gpu.module(&src)?;
        let d = &gpu.device;
        let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tracer-gpu"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage(1, true),
                storage(2, false),
                storage(3, false),
                storage(4, false),
                storage(5, true),
            ],
        });
        let pl = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tracer-gpu"),
            bind_group_layouts: &[&layout],
            push_constant_ranges: &[],
        });
        gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipe = |entry: &str| {
            d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pl),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let px = pipe("main_px");
        let cell = pipe("main_cell");
        if let Some(e) = pollster::block_on(gpu.device.pop_error_scope()) {
            return Err(format!("the generated shader does not compile: {e}"));
        }
        Ok(Tracer {
            gpu,
            arith,
            layout,
            px,
            cell,
        })
    }

    /// The arithmetic this tracer evaluates in.
    pub fn arith(&self) -> GpuArith {
        self.arith
    }

    /// Uploads `frame`. Errors on a ray count that does not match the size, or cells
    /// that do not cover the image.
    pub fn prepare(&self, frame: &Frame) -> Result<Prepared, String> {
        let n = frame.width as usize * frame.height as usize;
        if frame.rays.len() != n {
            return Err(format!(
                "{} rays for a {}x{} image",
                frame.rays.len(),
                frame.width,
                frame.height
            ));
        }
        let d = &self.gpu.device;
        let (culling, cell, cells_x, cell_jobs) = match &frame.cells {
            Some(c) => {
                let rows = frame.height.div_ceil(c.cell.max(1));
                if c.cell == 0
                    || c.cells_x != frame.width.div_ceil(c.cell)
                    || c.bundles.len() != (c.cells_x * rows) as usize
                {
                    return Err("the culling cells do not cover the image".into());
                }
                let jobs: Vec<Job> = c.bundles.iter().map(|b| b.to_job()).collect();
                (true, c.cell, c.cells_x, jobs)
            }
            None => (false, 1, 1, vec![Bundle::miss().to_job()]),
        };
        let pos = |v: f64| {
            if v > 0.0 && v.is_finite() {
                convert::up(v)
            } else {
                0.0
            }
        };
        let params = Params {
            zero: 0,
            eps_abs: pos(frame.eps_abs),
            eps_rel: pos(frame.eps_rel),
            width: frame.width,
            height: frame.height,
            cell,
            cells_x,
            culling: culling as u32,
            pruning: frame.pruning as u32,
            max_iter: 4096,
            normal_h: pos(frame.normal_h),
            refine: 1.0 / 4096.0,
        };
        let jobs: Vec<Job> = frame.rays.iter().map(|b| b.to_job()).collect();
        let uni = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let init = |data: &[u8], usage| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: data,
                usage,
            })
        };
        let st = wgpu::BufferUsages::STORAGE;
        let jobs_b = init(bytemuck::cast_slice(&jobs), st);
        let cell_jobs_b = init(bytemuck::cast_slice(&cell_jobs), st);
        let out = |bytes: usize| {
            d.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: bytes.max(4) as u64,
                usage: st | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let out_px = out(n * 16);
        let out_st = out(n * 4);
        let cells = out(cell_jobs.len() * 4);
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.layout,
            entries: &[
                entry_of(0, &uni),
                entry_of(1, &jobs_b),
                entry_of(2, &out_px),
                entry_of(3, &out_st),
                entry_of(4, &cells),
                entry_of(5, &cell_jobs_b),
            ],
        });
        Ok(Prepared {
            width: frame.width,
            height: frame.height,
            ncells: cell_jobs.len() as u32,
            culling,
            bind,
            out_px,
            out_st,
            cells,
        })
    }

    /// Runs the frame's passes and waits for them; returns the GPU time (submission to
    /// completion).
    pub fn run(&self, p: &Prepared) -> Result<Duration, String> {
        let start = Instant::now();
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_bind_group(0, &p.bind, &[]);
            if p.culling {
                pass.set_pipeline(&self.cell);
                pass.dispatch_workgroups(p.ncells.div_ceil(64), 1, 1);
            }
            pass.set_pipeline(&self.px);
            pass.dispatch_workgroups(p.width.div_ceil(8), p.height.div_ceil(8), 1);
        }
        self.gpu.queue.submit([enc.finish()]);
        self.gpu.wait()?;
        Ok(start.elapsed())
    }

    /// The results of the last [`Tracer::run`] of `p`.
    pub fn read(&self, p: &Prepared) -> Result<Output, String> {
        let n = p.width as usize * p.height as usize;
        let px = self.gpu.read_u32(&p.out_px, n * 4)?;
        let st = self.gpu.read_u32(&p.out_st, n)?;
        let cells_culled = if p.culling {
            let c = self.gpu.read_u32(&p.cells, p.ncells as usize)?;
            c.iter().filter(|&&v| v == 0).count() as u64
        } else {
            0
        };
        let f = |w: u32| f32::from_bits(w);
        Ok(Output {
            width: p.width,
            height: p.height,
            status: st
                .iter()
                .map(|&s| match s & 3 {
                    0 => Status::Miss,
                    1 => Status::Hit,
                    2 => Status::Unconfirmed,
                    _ => Status::Culled,
                })
                .collect(),
            depth: px.chunks_exact(4).map(|c| f(c[0])).collect(),
            normal: px
                .chunks_exact(4)
                .map(|c| [f(c[1]), f(c[2]), f(c[3])])
                .collect(),
            evals: st.iter().map(|&s| s >> 2).collect(),
            cells_culled,
        })
    }

    /// [`Tracer::prepare`], [`Tracer::run`] and [`Tracer::read`] of one frame.
    pub fn render(&self, frame: &Frame) -> Result<Output, String> {
        let p = self.prepare(frame)?;
        self.run(&p)?;
        self.read(&p)
    }
}

impl Bundle {
    /// A bundle that misses (an empty parameter range).
    pub fn miss() -> Bundle {
        Bundle {
            origin: [0.0; 3],
            origin_rad: [0.0; 3],
            dir: [0.0, 0.0, 1.0],
            dir_rad: [0.0; 3],
            s0: 1.0,
            s1: 0.0,
        }
    }
}
