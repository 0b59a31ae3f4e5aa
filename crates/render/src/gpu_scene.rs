//! A scene on the GPU: its splats (world space, materials applied) as
//! instances in vertex buffers, in group order when the mode draws groups.
//!
//! Splats live in instance (vertex) buffers rather than storage buffers,
//! because lavapipe caps a storage binding at 128 MiB. Buffers are split into
//! chunks of at most [`MAX_CHUNK_BYTES`] so that no single allocation nears a
//! driver's buffer-size limit; a 2.3M-point cloud takes three 32 MiB chunks.
//! The same buffers are bound as storage by the tile pipeline (`tiled`),
//! one chunk per dispatch.

use wgpu::util::DeviceExt;

use super::changed_records::{PIECE, Rewrite, keys_of, record_key, write_changed};
use super::gpu_data::{SplatInstance, SplatLight, TriangleVertex};
use super::instance_layout::InstanceLayout;
use super::instance_order::InstanceOrder;
use super::live_mask::LiveMask;
use super::node_pool::{SlotPool, VACANT};
use crate::cloud::PointCloud;
use crate::frame::subset::NodeSpans;
use crate::grouping::Grouping;

/// Largest vertex buffer made for one chunk of splats.
pub const MAX_CHUNK_BYTES: usize = 32 << 20;

/// The splats of one scene, uploaded.
pub struct GpuScene {
    pub chunks: Vec<(wgpu::Buffer, u32)>,
    /// The splats drawn: the instances the groups range over (the opaque
    /// run of a mixed scene and a node pool's vacant slots not counted).
    pub len: usize,
    pub mean_radius: f32,
    /// Instance ranges of the groups (one range over everything when ungrouped).
    pub groups: Vec<std::ops::Range<u32>>,
    /// The transparent splats of each group: its whole run, or, in a grouped
    /// scene of transparent and opaque splats, the run's first part (the
    /// opaque ones follow it). What the transparent grouped modes blend.
    pub transparent_groups: Vec<std::ops::Range<u32>>,
    /// In a grouped scene of transparent and opaque splats, every opaque
    /// splat once at its own radius, after the groups (beyond [`Self::len`]):
    /// what the transparent grouped modes draw in high quality beneath the
    /// transparent layers (Zhang & Pajarola Fig. 18/19). Empty otherwise.
    pub opaque: std::ops::Range<u32>,
    /// The colour of every splat, when they all have the same one: colour
    /// targets then hold only the weights.
    pub uniform_colour: Option<[u8; 3]>,
    /// Whether some splat is less than opaque.
    pub transparent: bool,
    /// For a transparent scene, the records to sort each group (or the one
    /// group of everything) back to front for modes that blend in order (a
    /// CPU copy of the instances: 36 bytes each).
    /// Changed only through `&mut self`: the frame's preparation sorts it
    /// for its view before the plan runs ([`Self::order_back_to_front`]).
    order: Option<InstanceOrder>,
    /// The scene's environment map, when it has one (see [`Self::set_environment`]).
    pub environment: Option<super::environment_texture::EnvTexture>,
    /// How the device it lives on can keep sums of fragments.
    pub sums: super::targets::SumPrecision,
    /// The cloud index of each instance slot (as uploaded).
    slots: Vec<u32>,
    /// In a frame lit by scene lights: each chunk's shadow coefficients
    /// (`SplatLight` per instance), and what they were computed for.
    lights: Option<(Vec<wgpu::Buffer>, u64)>,
    /// The keys of the records as last written (`changed_records`; empty
    /// until a scene moves or a node pool is uploaded), so the next
    /// [`Self::rewrite`] writes only what changed.
    records: Vec<u64>,
    /// The mesh triangles a frame draws beside the splats, if any.
    pub triangles: Option<TriangleDraw>,
    /// Where a streamed selection's nodes sit, when its splats are pooled by node.
    pool: Option<SlotPool>,
    /// Where the instance ranges a pass draws lie in the slots, when not
    /// where they say (a node pool's: see `InstanceLayout::draw_map`).
    draw_map: Option<Vec<(u32, std::ops::Range<u32>)>>,
    /// Which slots hold a splat drawn (not a node pool's vacant or resident ones).
    live: LiveMask,
}

/// How a [`GpuScene`]'s slots hold a cloud's splats.
#[derive(Debug, Clone, Copy)]
pub enum Arrangement<'a> {
    /// In the cloud's order, or group by group in a grouping's order.
    Packed(Option<&'a Grouping>),
    /// Node by node, each drawn node kept in its slots ([`crate::node_pool`]),
    /// in group order within each node when a grouping (one group per splat) is given.
    Pooled(&'a NodeSpans, Option<&'a Grouping>),
}

/// What a frame of part of a scene's splats takes from the whole scene (see
/// [`GpuScene::set_triangles`]), found once: each is a pass over every splat.
#[derive(Debug, Clone, Copy)]
pub struct WholeScene {
    pub uniform_colour: Option<[u8; 3]>,
    pub transparent: bool,
}

impl WholeScene {
    pub fn of(cloud: &PointCloud) -> Self {
        Self { uniform_colour: uniform_colour(cloud), transparent: cloud.has_transparency() }
    }
}

/// A scene's mesh triangles on the GPU (three unshared vertices each, see
/// [`TriangleVertex`]) and the ranges of them a frame draws.
#[derive(Debug, Clone)]
pub struct TriangleDraw {
    pub buffer: std::sync::Arc<wgpu::Buffer>,
    /// Triangle ranges drawn.
    pub ranges: Vec<std::ops::Range<u32>>,
    /// The same as a list of triangle indices, for the tile pipeline.
    pub indices: std::sync::Arc<wgpu::Buffer>,
    /// Cull triangles facing away by their winding before rasterising them:
    /// every triangle is one-sided and the frame culls back faces (the
    /// fragment stage culls them exactly anyway; this saves their fragments).
    pub cull_back: bool,
}

impl TriangleDraw {
    /// Uploads `triangles` (indices of `cloud`, the flattened scene: materials applied).
    pub fn upload(
        device: &wgpu::Device,
        cloud: &PointCloud,
        triangles: impl Iterator<Item = [u32; 3]>,
    ) -> wgpu::Buffer {
        let mut vertices = Vec::new();
        for t in triangles {
            let [a, b, c] = t.map(|v| cloud.positions[v as usize]);
            let face = (b - a).cross(c - a).normalize_or_zero().to_array();
            for v in t.map(|v| v as usize) {
                let [r, g, b] = cloud.colours[v];
                vertices.push(TriangleVertex {
                    position: cloud.positions[v].to_array(),
                    sided: if cloud.is_two_sided(v) { -1.0 } else { 1.0 },
                    normal: cloud.normals[v].to_array(),
                    colour: [r, g, b, 255],
                    opacity: cloud.opacity[v],
                    face,
                });
            }
        }
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("GpuScene::triangles"),
            contents: bytemuck::cast_slice(&vertices),
            // STORAGE: the tile pipeline reads the triangles in compute passes.
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
        })
    }

    /// The triangles drawn, by index, for the tile pipeline (`indices`).
    pub fn upload_indices(device: &wgpu::Device, ranges: &[std::ops::Range<u32>]) -> wgpu::Buffer {
        let indices: Vec<u32> = ranges.iter().flat_map(|r| r.clone()).collect();
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("GpuScene::drawn_triangles"),
            contents: bytemuck::cast_slice(if indices.is_empty() { &[0u32][..] } else { &indices }),
            usage: wgpu::BufferUsages::STORAGE,
        })
    }

    /// Triangles drawn.
    pub fn count(&self) -> u32 {
        self.ranges.iter().map(|r| r.len() as u32).sum()
    }
}

/// The colour of every splat, when they all have the same one.
fn uniform_colour(cloud: &PointCloud) -> Option<[u8; 3]> {
    let first = cloud.colours.first().copied();
    first.filter(|c| cloud.colours.iter().all(|x| x == c))
}

impl GpuScene {
    /// Uploads a scene's splats in world space (`Scene::flatten`) in scene
    /// order, or group by group (each group contiguous, with its radius scale)
    /// when a grouping of them is given.
    pub fn upload_cloud(device: &wgpu::Device, cloud: &PointCloud, grouping: Option<&Grouping>) -> Self {
        // Only a transparent scene is ever drawn in order (opaque ones run opaque plans).
        let transparent = cloud.has_transparency();
        Self::upload_layout(device, cloud, packed(cloud, grouping), (transparent, false))
    }

    /// Uploads a scene's splats in world space arranged as `arrangement` says.
    pub fn upload_arranged(device: &wgpu::Device, cloud: &PointCloud, arrangement: Arrangement<'_>) -> Self {
        match arrangement {
            Arrangement::Packed(grouping) => Self::upload_cloud(device, cloud, grouping),
            Arrangement::Pooled(spans, grouping) => {
                let (pool, placement) = SlotPool::laid_out(spans);
                let layout = InstanceLayout::pooled(&placement, spans, grouping);
                let mut upload = Self::upload_layout(device, cloud, layout, (false, true));
                upload.pool = Some(pool);
                upload
            }
        }
    }

    /// Uploads `layout`'s records; keeps them on the CPU to sort them
    /// (`keep_for_order`) or to write only what changed in the next
    /// selection (`mirror`: a node pool's).
    fn upload_layout(
        device: &wgpu::Device,
        cloud: &PointCloud,
        layout: InstanceLayout,
        (keep_for_order, mirror): (bool, bool),
    ) -> Self {
        let per_chunk = per_chunk(device);
        let mut chunks = Vec::new();
        let (mut kept, mut records) = (Vec::new(), Vec::new());
        let mut start = 0;
        while start < layout.order.len() {
            let end = (start + per_chunk).min(layout.order.len());
            let instances = layout.instances(cloud, start..end);
            let buffer = splat_buffer(device, &instances);
            chunks.push((buffer, (end - start) as u32));
            if keep_for_order {
                kept.extend_from_slice(&instances);
            }
            if mirror {
                records.extend(keys_of(&instances));
            }
            start = end;
        }
        let live = LiveMask::new(device, layout.live_bits());
        let InstanceLayout { order, groups, transparent_groups, opaque, draw_map: layout_map, .. } = layout;
        let instance_order = keep_for_order.then(|| InstanceOrder::new(kept, transparent_groups.clone()));
        Self {
            chunks,
            len: opaque.start as usize,
            mean_radius: cloud.mean_radius(),
            groups,
            transparent_groups,
            opaque,
            uniform_colour: uniform_colour(cloud),
            transparent: cloud.has_transparency(),
            order: instance_order,
            environment: None,
            sums: super::targets::SumPrecision::of(device),
            slots: order,
            lights: None,
            records,
            triangles: None,
            pool: None,
            draw_map: layout_map,
            live,
        }
    }

    /// Draws `triangles` beside the splats from now on, with the single
    /// colour and the transparency of the `whole` scene they belong to, as a
    /// frame of every splat would (the splats drawn beside them are a part;
    /// ε is the whole scene's too, as the frame's spec says).
    pub fn set_triangles(&mut self, triangles: Option<TriangleDraw>, whole: &WholeScene) {
        if triangles.is_some() {
            self.uniform_colour = whole.uniform_colour;
            self.transparent |= whole.transparent;
        }
        self.triangles = triangles;
    }

    /// Instance slots in the buffers: [`Self::len`] and, in a node pool, the vacant ones.
    pub fn slot_count(&self) -> usize {
        self.chunks.iter().map(|(_, n)| *n as usize).sum()
    }

    /// Bytes of the splat records on the GPU (what uploading them wrote).
    pub fn splat_bytes(&self) -> u64 {
        self.chunks.iter().map(|(_, n)| *n as u64).sum::<u64>() * std::mem::size_of::<SplatInstance>() as u64
    }

    /// Replaces the splats with another frame's (`cloud`, arranged as
    /// `arrangement` says) in the same buffers when the instance count
    /// and chunks stay (a deforming model, or a node pool that kept its
    /// capacity: only the runs of records that changed are written), else
    /// in new ones. Returns the bytes written.
    /// Shadow coefficients are dropped: the next [`Self::set_shadows`] writes them.
    pub fn rewrite(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        cloud: &PointCloud,
        arrangement: Arrangement<'_>,
    ) -> u64 {
        let layout = match arrangement {
            Arrangement::Packed(grouping) => {
                self.pool = None;
                packed(cloud, grouping)
            }
            Arrangement::Pooled(spans, grouping) => {
                let placement = match &mut self.pool {
                    Some(pool) => pool.place(spans),
                    None => {
                        let (pool, placement) = SlotPool::laid_out(spans);
                        self.pool = Some(pool);
                        placement
                    }
                };
                InstanceLayout::pooled(&placement, spans, grouping)
            }
        };
        let mut slots = self.slot_count();
        let transparent = cloud.has_transparency();
        let record = std::mem::size_of::<SplatInstance>() as u64;
        let mut written = 0u64;
        // A node pool that grew keeps its slots and adds chunks for the new
        // ones, written below only where a node now lies: no pass reads a
        // vacant slot of a pool (the raster passes draw the placed runs,
        // `tiled` the live slots), so the new ones are kept as if vacant.
        let grew = layout.order.len() > slots && slots > 0 && self.records.len() == slots;
        if grew && self.pool.is_some() && transparent == self.transparent {
            let vacant = record_key(&SplatInstance::VACANT);
            for chunk in (slots..layout.order.len()).step_by(per_chunk(device)) {
                let end = (chunk + per_chunk(device)).min(layout.order.len());
                self.chunks.push((empty_splat_buffer(device, end - chunk), (end - chunk) as u32));
                self.records.resize(end, vacant);
            }
            slots = layout.order.len();
        }
        if layout.order.len() != slots || transparent != self.transparent || slots == 0 {
            let (environment, pool) = (self.environment.take(), self.pool.take());
            let mirror = pool.is_some();
            *self = Self::upload_layout(device, cloud, layout, (transparent, mirror));
            (self.environment, self.pool) = (environment, pool);
            return self.slots.len() as u64 * record;
        }
        // A transparent scene's buffers hold its records sorted for the last
        // view (`InstanceOrder`), not in slot order: every record is written then.
        let all = self.records.len() != slots || self.order.is_some();
        if all {
            self.records = vec![0; slots];
        }
        let mut sorted = self.order.is_some().then(Vec::new);
        let mut chunk_start = 0usize;
        for (buffer, count) in &self.chunks {
            let chunk_end = chunk_start + *count as usize;
            for piece in (chunk_start..chunk_end).step_by(PIECE) {
                let end = (piece + PIECE).min(chunk_end);
                let instances = layout.instances(cloud, piece..end);
                let kept = &mut self.records[piece..end];
                let leave = layout.kept_in(piece..end);
                let how = if all { Rewrite::All } else { Rewrite::Changed { leave: &leave } };
                written += write_changed(queue, (buffer, piece - chunk_start), &instances, kept, how);
                if let Some(sorted) = &mut sorted {
                    sorted.extend(instances);
                }
            }
            chunk_start = chunk_end;
        }
        if let (Some(order), Some(records)) = (&mut self.order, sorted) {
            *order = InstanceOrder::new(records, layout.transparent_groups.clone());
        }
        written += self.live.write(device, queue, layout.live_bits());
        let InstanceLayout { order, groups, transparent_groups, opaque, draw_map, .. } = layout;
        self.draw_map = draw_map;
        self.len = opaque.start as usize;
        self.mean_radius = cloud.mean_radius();
        self.groups = groups;
        self.transparent_groups = transparent_groups;
        self.opaque = opaque;
        self.uniform_colour = uniform_colour(cloud);
        self.slots = order;
        self.lights = None;
        written
    }

    /// The live mask: a bit per slot, set where a slot holds a splat drawn.
    pub fn live_mask(&self) -> &wgpu::Buffer {
        self.live.buffer()
    }

    /// When the splats are pooled by node: the nodes drawn, and those kept on the GPU undrawn.
    pub fn pooled_nodes(&self) -> Option<(usize, usize)> {
        self.pool.as_ref().map(|pool| (pool.drawn(), pool.residents()))
    }

    /// Uploads each splat's shadow coefficients (`key` names what they were
    /// computed for), or drops them (`None`: a frame without lights).
    pub fn set_shadows(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        shadows: Option<(&crate::shadow::ShadowCoefficients, u64)>,
    ) {
        let Some((coefficients, key)) = shadows else {
            self.lights = None;
            return;
        };
        if self.shadow_key() == Some(key) {
            return;
        }
        let per_slot: Vec<SplatLight> = self
            .slots
            .iter()
            .map(|&i| if i == VACANT { SplatLight::default() } else { coefficients.bytes(i as usize) })
            .collect();
        let buffers = match self.lights.take() {
            Some((buffers, _)) => buffers,
            None => self
                .chunks
                .iter()
                .map(|(_, count)| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("GpuScene::shadow_coefficients"),
                        size: (*count as u64 * std::mem::size_of::<SplatLight>() as u64).max(4),
                        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                })
                .collect(),
        };
        match &mut self.order {
            Some(order) => order.set_lights(queue, per_slot, &self.chunks, &buffers),
            None => {
                let mut start = 0usize;
                for ((_, count), buffer) in self.chunks.iter().zip(&buffers) {
                    let end = start + *count as usize;
                    queue.write_buffer(buffer, 0, bytemuck::cast_slice(&per_slot[start..end]));
                    start = end;
                }
            }
        }
        self.lights = Some((buffers, key));
    }

    /// What a frame of this upload alone is decided over (a bare upload, as
    /// tests and `render_image` draw it): its splats, transparency and mean
    /// radius, whether it draws triangles, and whether shadow coefficients are uploaded.
    pub fn facts(&self) -> crate::frame::SceneFacts {
        crate::frame::SceneFacts {
            splats: self.len,
            transparent: self.transparent,
            surfaces: self.triangles.is_some(),
            moving: false,
            streamed: false,
            mean_radius: self.mean_radius,
            shadows_at_hand: self.light_chunks().is_some(),
        }
    }

    /// What the uploaded shadow coefficients were computed for, if any are.
    pub fn shadow_key(&self) -> Option<u64> {
        self.lights.as_ref().map(|(_, key)| *key)
    }

    /// Each chunk's shadow-coefficient buffer, in a frame lit by scene lights.
    pub fn light_chunks(&self) -> Option<&[wgpu::Buffer]> {
        self.lights.as_ref().map(|(buffers, _)| buffers.as_slice())
    }

    /// Uploads the environment map transparent surfaces reflect and refract
    /// (or drops it).
    pub fn set_environment(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        map: Option<&crate::scene::environment_map::EnvironmentMap>,
    ) {
        self.environment = map.map(|m| super::environment_texture::EnvTexture::upload(device, queue, m));
    }

    /// Sorts each group's instances back to front for `view` (a transparent
    /// scene; others are left as they are); returns whether the buffers were
    /// rewritten (not when the view is the last one's).
    pub fn order_back_to_front(
        &mut self,
        queue: &wgpu::Queue,
        view: crate::spatial::order::ViewRay,
        kind: crate::spatial::order::OrderKind,
    ) -> bool {
        let Some(order) = &mut self.order else { return false };
        let lights = self.lights.as_ref().map(|(buffers, _)| buffers.as_slice());
        order.apply(queue, &self.chunks, lights, view, kind)
    }

    /// The scene's instance order, if it keeps one.
    pub fn instance_order(&self) -> Option<&InstanceOrder> {
        self.order.as_ref()
    }

    /// All splats, as an instance range (without the opaque run).
    pub fn all(&self) -> std::ops::Range<u32> {
        0..self.len as u32
    }

    /// Draws the instances `range` as 4-vertex strips; the pipeline must be
    /// set. The range is one of the groups' (or within every splat's), and
    /// is drawn where its splats lie: the same slots, or in a node pool
    /// the runs of slots the draw map gives (vacant slots are never drawn).
    pub fn draw_range(&self, pass: &mut wgpu::RenderPass<'_>, range: std::ops::Range<u32>) {
        let Some(map) = &self.draw_map else { return self.draw_slots(pass, range) };
        // The first run that ends past the range's start, then those that begin before its end.
        let first = map.partition_point(|(drawn, slots)| drawn + slots.len() as u32 <= range.start);
        for (drawn, slots) in map[first..].iter().take_while(|(drawn, _)| *drawn < range.end) {
            let from = range.start.max(*drawn) - drawn + slots.start;
            let to = range.end.min(drawn + slots.len() as u32) - drawn + slots.start;
            if from < to {
                self.draw_slots(pass, from..to);
            }
        }
    }

    fn draw_slots(&self, pass: &mut wgpu::RenderPass<'_>, range: std::ops::Range<u32>) {
        let mut chunk_start = 0u32;
        for (k, (buffer, count)) in self.chunks.iter().enumerate() {
            let chunk_end = chunk_start + count;
            let (from, to) = (range.start.max(chunk_start), range.end.min(chunk_end));
            if from < to {
                pass.set_vertex_buffer(0, buffer.slice(..));
                if let Some(lights) = self.light_chunks() {
                    pass.set_vertex_buffer(1, lights[k].slice(..));
                }
                pass.draw(0..4, from - chunk_start..to - chunk_start);
            }
            chunk_start = chunk_end;
        }
    }
}

impl<'a> Arrangement<'a> {
    /// Pooled by the nodes `spans` where there are some and `grouping`
    /// (if any) puts each of their splats in one group, else packed.
    pub fn of(spans: Option<&'a NodeSpans>, grouping: Option<&'a Grouping>) -> Self {
        match spans {
            Some(spans) if grouping.is_none_or(|g| g.order.len() == spans.splats() as usize) => {
                Arrangement::Pooled(spans, grouping)
            }
            _ => Arrangement::Packed(grouping),
        }
    }
}

/// Splat records per chunk: [`MAX_CHUNK_BYTES`] of them, or what one buffer may hold.
fn per_chunk(device: &wgpu::Device) -> usize {
    (MAX_CHUNK_BYTES / std::mem::size_of::<SplatInstance>())
        .min(device.limits().max_buffer_size as usize / std::mem::size_of::<SplatInstance>())
        .max(1)
}

/// One chunk of splat records on the GPU.
fn splat_buffer(device: &wgpu::Device, instances: &[SplatInstance]) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("GpuScene::splats"),
        contents: bytemuck::cast_slice(instances),
        // STORAGE: the tile pipeline reads the instances in compute passes.
        usage: wgpu::BufferUsages::VERTEX
            | wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
    })
}

/// A chunk of `count` splat records, zeroed (for a node pool's new slots).
fn empty_splat_buffer(device: &wgpu::Device, count: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("GpuScene::splats"),
        size: (count * std::mem::size_of::<SplatInstance>()) as u64,
        usage: wgpu::BufferUsages::VERTEX
            | wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// The layout of `cloud` in its own order, or in `grouping`'s.
fn packed(cloud: &PointCloud, grouping: Option<&Grouping>) -> InstanceLayout {
    match grouping {
        Some(g) => InstanceLayout::grouped(cloud, &g.order, &g.radius_scale, &g.ranges),
        None => InstanceLayout::plain(cloud),
    }
}
