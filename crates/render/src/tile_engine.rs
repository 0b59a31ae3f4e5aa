//! The tile pipeline behind `tiled`: the exact reference's algorithm
//! (crates/core/src/reference/raster.rs) as GPU compute, in four passes
//! over buffers this engine owns.
//!
//! 1. **Project** (per splat, one dispatch per chunk of the scene's
//!    instance buffers, bound as storage): eye space, footprint plane,
//!    the tiles the disc may cover, counted per tile with atomics.
//! 2. **Scan** (one workgroup): the counts' prefix sum into the tiles'
//!    offsets, on the GPU (shaders/tiled_scan.wgsl). The entry buffer has
//!    a given room, as a bump allocator in vello has: when the total passes
//!    it, the scan raises an overflow flag and leaves every list empty. The
//!    flag comes back with the frame's result ([`TileEngine::finish_frame`]),
//!    and the renderer draws the frame again with room for the total, which
//!    later frames keep. Nothing is read back inside a frame, and no tile
//!    list is ever cut short in a frame that is kept. A total beyond what
//!    one storage binding or the frame's memory holds is
//!    [`GpuError::TilesDoNotFit`]: the frame is drawn in smaller parts of
//!    the screen (gpu_renderer.rs), never with a dropped splat.
//!
//! The per-splat buffers (eye records, pixel boxes) have a slot per splat
//! when those fit one storage binding and half the frame's memory. A scene
//! with more splats gets as many slots as fit, and each part of the frame
//! packs the splats whose box reaches it into them (the projection counts
//! them; more than the slots overflow, and the part is cut smaller; the
//! sort then orders equal keys by each box's place in the scene, in a
//! variant of its own, `PACKED`). So the
//! memory of a frame is bounded by `POINTBLEND_GPU_MEMORY_MB` (or the
//! device's) at any splat count and size, beside the scene's own buffers.
//! 3. **Bin** (per splat): an entry (nearest depth on the disc, splat) in
//!    the list of each tile the disc meets. The projection counted every
//!    tile of the disc's pixel box (that bounds the memory); the binning
//!    tests the disc against each of them (the quadrilateral where the
//!    tile's corner rays meet the disc's plane), counts what it keeps, and
//!    the sort and raster read only those.
//! 4. **Sort** (per tile): the list in order of nearest depth: a short list
//!    by one invocation, a long one by a workgroup, in workgroup memory or,
//!    longer still, in place.
//! 5. **Raster** (per tile, per pixel): hits in depth order, ε-layers,
//!    front-to-back compositing (shaders/tiled_raster.wgsl).
//!
//! The sort is per tile on the GPU because no GPU sort crate is correct and
//! faster than the CPU here (wgpu_sort 0.1 misorders 100K keys on lavapipe;
//! lampshade is slower than a CPU sort), and a tile's list is short enough
//! for a bitonic network in one workgroup.

use super::context::{GpuContext, GpuError};
use super::gpu_scene::GpuScene;
use super::passes::{ComputePass, TileWork};
use super::shaders::Variant;
use super::tile_buffers::{GROUP, INDIRECT, READBACK, STORAGE, buffer, dispatch, grid_uniform, mib, read};

/// Side of a square tile in pixels. Mirrors `TILE` in shaders/tiled_common.wgsl.
/// Every pixel of a tile tests every disc binned to it, so smaller tiles
/// test fewer discs that miss, and bin more entries. Measured on the
/// transparent bunny at 512² (lavapipe): 16 px 702 ms, 8 px 485 ms, 4 px 908 ms.
pub const TILE: u32 = 8;
/// Hits a pixel keeps waiting in registers (`WINDOW` in
/// shaders/tiled_raster.wgsl); a pixel with more waiting and none ready is
/// finished a layer at a time, exactly, and counted.
pub const WINDOW: u32 = 8;
/// Bytes of one splat in eye space (`EyeSplat` in shaders/tiled_common.wgsl).
pub const EYE_SPLAT_BYTES: u64 = 48;
/// Bytes of a splat's pixel rectangle and sort key.
pub const RECT_BYTES: u64 = 16;
/// Bytes of one (key, splat) entry of a tile list.
pub const ENTRY_BYTES: u64 = 8;
/// Lists up to this long are sorted by one invocation, by insertion; longer
/// ones by a workgroup (`SHORT` in shaders/tiled_common.wgsl). A workgroup's
/// barriers cost more than a short list's insertion sort on lavapipe: with
/// a workgroup for every list the sort took 40 of 350 ms on the bunny.
pub const SHORT_LIST: u32 = 4096;

/// One dispatch of a pass: its group-1 resources, and its size in
/// workgroups (`None`: the size the scan wrote, an indirect dispatch).
type Dispatched<'a> = (Vec<wgpu::BindingResource<'a>>, Option<(u32, u32)>);

/// Tile columns and rows of a `width` x `height` frame.
pub fn grid(width: u32, height: u32) -> (u32, u32) {
    (width.div_ceil(TILE), height.div_ceil(TILE))
}

/// What the last frame's tile pipeline met, read with its result.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TileStats {
    /// Splats whose pixel box reached the frame, when they were packed into
    /// fewer slots than the scene has splats (past the slots too).
    pub packed: Option<u64>,
    /// (tile, splat) entries counted over the discs' pixel boxes, which
    /// the entry buffer makes room for (`u32::MAX` when they passed it).
    pub entries: u64,
    /// Of those, the entries kept: the discs that meet their tile.
    pub kept: u64,
    /// Longest tile list.
    pub longest_list: u32,
    /// Whether the entries passed the room the frame was drawn with (its
    /// lists were left empty; the renderer draws it again).
    pub overflow: bool,
    /// Pixels whose sorting window overflowed and which were finished a
    /// layer at a time (see shaders/tiled_raster.wgsl).
    pub window_overflows: u32,
}

/// Bytes of the lists' state (`lists` in shaders/tiled_common.wgsl): the
/// room, the total, the overflow flag, the longest list, cs_sort's dispatch,
/// the splats packed into the per-splat slots.
pub(crate) const LIST_STATE_BYTES: u64 = 32;
/// Word of the lists' state that counts the packed splats (`PACKED`).
const PACKED_WORD: usize = 7;
/// Bytes of the raster's counters (`stats` in shaders/tiled_raster.wgsl).
const RASTER_STATS_BYTES: u64 = 16;
/// Bytes read back after a frame: the lists' state, then the raster's counters.
pub(crate) const READBACK_BYTES: u64 = LIST_STATE_BYTES + RASTER_STATS_BYTES;
/// Byte offset of cs_sort's indirect dispatch in the lists' state.
const LONG_DISPATCH_OFFSET: u64 = 16;
/// Entries the first frame of an engine has room for, per splat or
/// triangle: a guess, which an overflow corrects once.
pub const FIRST_ROOM_PER_ITEM: u64 = 4;

/// The buffers of the tile pipeline, sized for the last frame.
pub struct TileEngine {
    /// The scene's splat slots.
    splats: u64,
    /// Slots of the per-splat buffers: `splats`, or fewer when those would
    /// pass one storage binding or half the frame's memory, and then the
    /// splats that reach the frame are packed into them (shaders/tiled_project.wgsl).
    slots: u64,
    /// Mesh triangles binned after the splats (items `splats..splats + triangles`).
    triangles: u64,
    grid: (u32, u32),
    eye: wgpu::Buffer,
    rects: wgpu::Buffer,
    counts: wgpu::Buffer,
    /// Each tile's first entry (and the total), then the entries its
    /// binning kept (the discs that meet the tile, of those counted).
    offsets: wgpu::Buffer,
    entries: wgpu::Buffer,
    /// As large as `entries`: the merge sort's other half.
    scratch: wgpu::Buffer,
    entry_capacity: u64,
    /// The lists' state ([`LIST_STATE_BYTES`]), also cs_sort's indirect dispatch.
    lists: wgpu::Buffer,
    /// The raster's counters.
    stats: wgpu::Buffer,
    /// The lists' state and the raster's counters, read after the frame.
    readback: wgpu::Buffer,
    /// How many tiles have lists longer than [`SHORT_LIST`], then those tiles.
    long_tiles: wgpu::Buffer,
    /// Per chunk of the scene: the project pass's grid uniforms; then one
    /// over every item (z: the first triangle's item), and the triangles'.
    uniforms: Vec<(wgpu::Buffer, u32)>,
    all: wgpu::Buffer,
    triangle_uniform: wgpu::Buffer,
    pub last: TileStats,
}

impl TileEngine {
    /// An engine for `scene` at `size`, whose per-splat buffers and lists
    /// take at most `budget` bytes (the frame's memory beside its targets):
    /// a slot per splat when they fit one storage binding and half the
    /// budget, else as many slots as do, into which each part of the frame
    /// packs the splats that reach it.
    pub fn new(ctx: &GpuContext, scene: &GpuScene, size: (u32, u32), budget: u64) -> Result<Self, GpuError> {
        let device = &ctx.device;
        // Every slot is projected (those the scene's live mask leaves out are culled there).
        let n = scene.slot_count() as u64;
        let m = scene.triangles.as_ref().map_or(0, |t| t.count() as u64);
        let limit = device.limits().max_storage_buffer_binding_size;
        if let Some(draw) = scene.triangles.as_ref().filter(|_| m > 0) {
            if draw.buffer.size() > limit || (m + 1) * RECT_BYTES > limit {
                return Err(GpuError::TooLarge(format!(
                    "tiled reads the mesh triangles ({:.1} MiB) and their pixel boxes ({:.1} MiB) from one storage buffer each, more than the {:.1} MiB this GPU binds; use another mode",
                    mib(draw.buffer.size()),
                    mib((m + 1) * RECT_BYTES),
                    mib(limit)
                )));
            }
        }
        let slots = Self::slots_for(ctx, n, m, budget);
        ctx.allocating("allocating the tile pipeline", || Self {
            splats: n,
            slots,
            triangles: m,
            grid: (0, 0),
            // One record at least: the raster binds a whole one even for a frame of triangles only.
            eye: buffer(device, "Tiles::eye", slots.max(1) * EYE_SPLAT_BYTES, STORAGE),
            rects: buffer(device, "Tiles::rects", (slots + m) * RECT_BYTES, STORAGE),
            counts: buffer(device, "Tiles::counts", 0, STORAGE),
            offsets: buffer(device, "Tiles::offsets", 0, STORAGE),
            entries: buffer(device, "Tiles::entries", 0, STORAGE),
            scratch: buffer(device, "Tiles::scratch", 0, STORAGE),
            entry_capacity: 0,
            lists: buffer(device, "Tiles::lists", LIST_STATE_BYTES, INDIRECT),
            stats: buffer(device, "Tiles::stats", RASTER_STATS_BYTES, STORAGE),
            readback: buffer(device, "Tiles::readback", READBACK_BYTES, READBACK),
            long_tiles: buffer(device, "Tiles::long_tiles", 0, STORAGE),
            all: buffer(device, "Tiles::grid", 0, wgpu::BufferUsages::UNIFORM),
            triangle_uniform: buffer(device, "Tiles::grid", 0, wgpu::BufferUsages::UNIFORM),
            uniforms: Vec::new(),
            last: TileStats::default(),
        })
        .and_then(|mut engine| {
            engine.set_grid(ctx, scene, size)?;
            Ok(engine)
        })
    }

    /// Slots of the per-splat buffers for `n` splats and `m` triangles
    /// within `budget`: every splat when the eye records fit one storage
    /// binding and the records and boxes half the budget (the lists take
    /// the other half), else as many as do (at least one).
    fn slots_for(ctx: &GpuContext, n: u64, m: u64, budget: u64) -> u64 {
        let limit = ctx.device.limits().max_storage_buffer_binding_size;
        let by_binding = (limit / EYE_SPLAT_BYTES).min((limit / RECT_BYTES).saturating_sub(m));
        let by_budget = (budget / 2 / (EYE_SPLAT_BYTES + RECT_BYTES)).saturating_sub(m);
        n.min(by_binding).min(by_budget).max(1)
    }

    /// Whether this engine's per-splat buffers serve `scene` within `budget`
    /// (any frame size: [`Self::set_grid`] sizes the per-tile ones).
    pub fn fits(&self, ctx: &GpuContext, scene: &GpuScene, budget: u64) -> bool {
        let n = scene.slot_count() as u64;
        let m = scene.triangles.as_ref().map_or(0, |t| t.count() as u64);
        // Slots within the budget, and not far fewer than it allows (the
        // parts of a frame have budgets a few tile tables apart).
        let wanted = Self::slots_for(ctx, n, m, budget);
        self.splats == n
            && self.triangles == m
            && self.slots <= wanted
            && (self.slots == n || self.slots * 8 >= wanted * 7)
            && self.uniforms.len() == scene.chunks.len()
            && self.uniforms.iter().zip(&scene.chunks).all(|((_, a), (_, b))| a == b)
    }

    /// Whether the splats that reach a frame are packed into fewer slots than the scene has.
    pub fn packing(&self) -> bool {
        self.slots < self.splats
    }

    /// Slots of the per-splat buffers.
    pub fn slots(&self) -> u64 {
        self.slots
    }

    /// Sizes the per-tile buffers and the passes' uniforms for a frame (or
    /// a part of one) of `size`; nothing is allocated when the grid is the last one's.
    pub fn set_grid(&mut self, ctx: &GpuContext, scene: &GpuScene, size: (u32, u32)) -> Result<(), GpuError> {
        let grid = grid(size.0, size.1);
        if grid == self.grid && self.uniforms.len() == scene.chunks.len() {
            return Ok(());
        }
        let device = &ctx.device;
        let tiles = (grid.0 * grid.1) as u64;
        let (n, m, slots) = (self.splats as u32, self.triangles as u32, self.slots as u32);
        let room = [slots, self.packing() as u32, n, 0];
        ctx.allocating("allocating the tile grid", || {
            let mut uniforms = Vec::new();
            let mut first = 0u32;
            for (_, count) in &scene.chunks {
                uniforms.push((grid_uniform(device, grid, (first, *count), room), *count));
                first += count;
            }
            self.uniforms = uniforms;
            self.counts = buffer(device, "Tiles::counts", tiles * 4, STORAGE);
            self.offsets = buffer(device, "Tiles::offsets", (2 * tiles + 1) * 4, STORAGE);
            self.long_tiles = buffer(device, "Tiles::long_tiles", (tiles + 1) * 4, STORAGE);
            // Splat items take the slots, the triangles' follow them.
            self.all = grid_uniform(device, grid, (slots, slots + m), room);
            self.triangle_uniform = grid_uniform(device, grid, (slots, m), room);
        })?;
        self.grid = grid;
        Ok(())
    }

    /// Records one pass of the pipeline. `outputs` are the storage views a
    /// raster writes (its image, then the glass layers). Returns the texture
    /// views its bind groups were made with, by binding.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        pass: &ComputePass,
        (pipeline, layout): (&wgpu::ComputePipeline, &wgpu::BindGroupLayout),
        (frame, offset): (&wgpu::BindGroup, u32),
        scene: &GpuScene,
        outputs: &[&wgpu::TextureView],
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Vec<(u32, wgpu::TextureView)> {
        let given = std::cell::RefCell::new(Vec::new());
        let group = |resources: Vec<wgpu::BindingResource<'_>>| {
            for (binding, resource) in resources.iter().enumerate() {
                if let wgpu::BindingResource::TextureView(view) = resource {
                    given.borrow_mut().push((binding as u32, (*view).clone()));
                }
            }
            let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
                .into_iter()
                .enumerate()
                .map(|(binding, resource)| wgpu::BindGroupEntry { binding: binding as u32, resource })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(pass.label), layout, entries: &entries })
        };
        let groups: Vec<(wgpu::BindGroup, Option<(u32, u32)>)> = self
            .dispatches(encoder, pass, scene, outputs)
            .into_iter()
            .map(|(resources, size)| (group(resources), size))
            .collect();
        {
            let mut compute = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(pass.label),
                timestamp_writes: timestamps,
            });
            compute.set_pipeline(pipeline);
            compute.set_bind_group(0, frame, &[offset]);
            for (bind, size) in &groups {
                compute.set_bind_group(1, bind, &[]);
                match size {
                    Some((x, y)) => compute.dispatch_workgroups(*x, *y, 1),
                    None => compute.dispatch_workgroups_indirect(&self.lists, LONG_DISPATCH_OFFSET),
                }
            }
        }
        if pass.work == TileWork::Raster {
            // What the frame met goes back with its result, in one copy to map.
            encoder.copy_buffer_to_buffer(&self.lists, 0, &self.readback, 0, LIST_STATE_BYTES);
            encoder.copy_buffer_to_buffer(&self.stats, 0, &self.readback, LIST_STATE_BYTES, RASTER_STATS_BYTES);
        }
        given.into_inner()
    }

    /// The group-1 resources of each dispatch of `pass` and its size in
    /// workgroups (a projection dispatches once per chunk of splats; `None`:
    /// the size the scan wrote), after clearing the buffers the pass counts into.
    fn dispatches<'a>(
        &'a self,
        encoder: &mut wgpu::CommandEncoder,
        pass: &ComputePass,
        scene: &'a GpuScene,
        outputs: &[&'a wgpu::TextureView],
    ) -> Vec<Dispatched<'a>> {
        let tiles = (self.grid.0 * self.grid.1) as u64;
        let mut groups = Vec::new();
        match pass.work {
            TileWork::Project => {
                encoder.clear_buffer(&self.counts, 0, None);
                let lights = scene.light_chunks().filter(|_| pass.variant.has(Variant::LIGHTS));
                for (k, ((uniform, count), (chunk, _))) in self.uniforms.iter().zip(&scene.chunks).enumerate() {
                    let mut resources = vec![
                        uniform.as_entire_binding(),
                        chunk.as_entire_binding(),
                        self.eye.as_entire_binding(),
                        self.rects.as_entire_binding(),
                        self.counts.as_entire_binding(),
                        scene.live_mask().as_entire_binding(),
                        self.lists.as_entire_binding(),
                    ];
                    if let Some(lights) = lights {
                        resources.push(lights[k].as_entire_binding());
                    }
                    groups.push((resources, Some(dispatch(*count as u64, GROUP))));
                }
            }
            TileWork::ProjectTriangles => {
                if let Some(draw) = &scene.triangles {
                    let resources = vec![
                        self.triangle_uniform.as_entire_binding(),
                        draw.buffer.as_entire_binding(),
                        draw.indices.as_entire_binding(),
                        self.rects.as_entire_binding(),
                        self.counts.as_entire_binding(),
                    ];
                    groups.push((resources, Some(dispatch(self.triangles, GROUP))));
                }
            }
            TileWork::Scan => {
                let resources = vec![
                    self.all.as_entire_binding(),
                    self.counts.as_entire_binding(),
                    self.offsets.as_entire_binding(),
                    self.long_tiles.as_entire_binding(),
                    self.lists.as_entire_binding(),
                ];
                groups.push((resources, Some((1, 1))));
            }
            TileWork::Bin => {
                let resources = vec![
                    self.all.as_entire_binding(),
                    self.rects.as_entire_binding(),
                    self.offsets.as_entire_binding(),
                    self.entries.as_entire_binding(),
                    self.eye.as_entire_binding(),
                    self.lists.as_entire_binding(),
                ];
                groups.push((resources, Some(dispatch(self.slots + self.triangles, GROUP))));
            }
            TileWork::SortShort => {
                let resources = vec![
                    self.all.as_entire_binding(),
                    self.offsets.as_entire_binding(),
                    self.entries.as_entire_binding(),
                    self.scratch.as_entire_binding(),
                    self.rects.as_entire_binding(),
                ];
                groups.push((resources, Some(dispatch(tiles, GROUP))));
            }
            TileWork::SortLong => {
                let resources = vec![
                    self.all.as_entire_binding(),
                    self.offsets.as_entire_binding(),
                    self.entries.as_entire_binding(),
                    self.scratch.as_entire_binding(),
                    self.rects.as_entire_binding(),
                    self.long_tiles.as_entire_binding(),
                ];
                groups.push((resources, None));
            }
            TileWork::Raster => {
                encoder.clear_buffer(&self.stats, 0, None);
                let mut resources = vec![
                    self.all.as_entire_binding(),
                    self.offsets.as_entire_binding(),
                    self.entries.as_entire_binding(),
                    self.eye.as_entire_binding(),
                ];
                let mut views = outputs.iter().map(|v| wgpu::BindingResource::TextureView(v));
                resources.extend(views.next());
                resources.push(self.stats.as_entire_binding());
                resources.push(self.rects.as_entire_binding());
                resources.extend(views);
                if let Some(draw) = scene.triangles.as_ref().filter(|_| pass.variant.has(Variant::TRIANGLES)) {
                    resources.extend([draw.buffer.as_entire_binding(), draw.indices.as_entire_binding()]);
                }
                groups.push((resources, Some(dispatch(tiles, 1))));
            }
        }
        groups
    }

    /// Before a frame is recorded: gives the entry buffer room (a first
    /// guess for a new engine) and tells the scan how much it has.
    /// `budget` is the memory left to the frame beside its targets.
    pub fn begin_frame(&mut self, ctx: &GpuContext, budget: u64) -> Result<(), GpuError> {
        if self.entry_capacity == 0 {
            let guess = ((self.slots + self.triangles) * FIRST_ROOM_PER_ITEM).max(1);
            self.make_room(ctx, guess.min(self.room_limit(ctx, budget)).max(1), budget)?;
        }
        let room = self.entry_capacity.min(u32::MAX as u64) as u32;
        ctx.queue.write_buffer(&self.lists, 0, bytemuck::bytes_of(&room));
        ctx.queue.write_buffer(&self.lists, PACKED_WORD as u64 * 4, bytemuck::bytes_of(&0u32));
        Ok(())
    }

    /// Bytes of the per-splat buffers (eye records, pixel boxes).
    fn slot_bytes(&self) -> u64 {
        self.slots * EYE_SPLAT_BYTES + (self.slots + self.triangles) * RECT_BYTES
    }

    /// The most entries a frame may hold: the entries and the sort's
    /// scratch take one binding each, both within what `budget` leaves
    /// beside the per-splat buffers.
    fn room_limit(&self, ctx: &GpuContext, budget: u64) -> u64 {
        let left = budget.saturating_sub(self.slot_bytes());
        ctx.device.limits().max_storage_buffer_binding_size.min(left / 2) / ENTRY_BYTES
    }

    /// Makes the entry buffer hold `total` entries, a quarter more so that
    /// a slowly moving camera does not reallocate every frame; when they
    /// cannot fit, [`GpuError::TilesDoNotFit`], which a frame answers by
    /// being drawn in smaller parts.
    pub fn make_room(&mut self, ctx: &GpuContext, total: u64, budget: u64) -> Result<(), GpuError> {
        let limit = self.room_limit(ctx, budget);
        if total > limit {
            let binding = ctx.device.limits().max_storage_buffer_binding_size;
            return Err(GpuError::TilesDoNotFit {
                message: format!(
                    "tiled would bin {total} (tile, splat) entries ({:.1} MiB, twice over with the sort's scratch), more than \
                     one storage binding ({:.1} MiB) or the memory left to the frame ({:.1} MiB) holds",
                    mib(total * ENTRY_BYTES),
                    mib(binding),
                    mib(budget.saturating_sub(self.slot_bytes()))
                ),
                over: total as f64 / limit.max(1) as f64,
            });
        }
        if total > self.entry_capacity {
            let capacity = (total + total / 4).min(limit);
            let bytes = capacity * ENTRY_BYTES;
            (self.entries, self.scratch) = ctx.allocating("allocating the tile entries", || {
                (
                    buffer(&ctx.device, "Tiles::entries", bytes, STORAGE),
                    buffer(&ctx.device, "Tiles::scratch", bytes, STORAGE),
                )
            })?;
            self.entry_capacity = capacity;
        }
        Ok(())
    }

    /// After a frame was submitted: reads what its lists met (waits for the
    /// GPU, as reading the frame's image does), keeps it as [`Self::last`]
    /// and returns it. When `overflow` is set the frame's lists were empty
    /// and it must be drawn again after [`Self::make_room`] for `entries`.
    pub fn finish_frame(&mut self, ctx: &GpuContext) -> Result<TileStats, GpuError> {
        let words: Vec<u32> = read(ctx, &self.readback)?;
        let word = |i: usize| words.get(i).copied().unwrap_or(0);
        let stats_at = (LIST_STATE_BYTES / 4) as usize;
        self.last = TileStats {
            packed: self.packing().then(|| word(PACKED_WORD) as u64),
            entries: word(1) as u64,
            longest_list: word(3),
            overflow: word(2) != 0,
            window_overflows: word(stats_at),
            kept: word(stats_at + 1) as u64,
        };
        Ok(self.last)
    }

    /// Entries the entry buffer has room for.
    pub fn entry_capacity(&self) -> u64 {
        self.entry_capacity
    }

    /// Bytes of the buffers it holds (the entry buffer at its capacity).
    pub fn bytes(&self) -> u64 {
        [
            &self.eye,
            &self.rects,
            &self.counts,
            &self.offsets,
            &self.entries,
            &self.scratch,
            &self.long_tiles,
            &self.lists,
            &self.readback,
        ]
        .iter()
        .map(|b| b.size())
        .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shaders_use_the_tile_size_and_list_limit_given_here() {
        let common = crate::shaders::compose("tiled_common.wgsl", Variant::NONE).unwrap();
        assert!(common.contains(&format!("const TILE: u32 = {TILE}u;")), "TILE differs from the shader's");
        let sort = crate::shaders::compose("tiled_sort.wgsl", Variant::NONE).unwrap();
        assert!(sort.contains("fn cs_sort("), "the sort composes");
        assert!(sort.contains(&format!("const SHORT: u32 = {SHORT_LIST}u;")), "SHORT_LIST differs from the shader's");
        let raster = crate::shaders::compose("tiled_raster.wgsl", Variant::NONE).unwrap();
        assert!(raster.contains(&format!("const WINDOW: u32 = {WINDOW}u;")), "WINDOW differs from the shader's");
        let scan = crate::shaders::compose("tiled_scan.wgsl", Variant::NONE).unwrap();
        let dispatch_at = LONG_DISPATCH_OFFSET / 4;
        assert!(scan.contains(&format!("const LONG_DISPATCH: u32 = {dispatch_at}u;")), "the dispatch's offset differs");
    }
}
