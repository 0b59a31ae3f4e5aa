//! One module per subcommand, plus the options they share and the headless
//! main job of `view`.

pub mod bench;
pub mod convert;
pub mod formats_help;
pub mod group;
pub mod info;
pub mod info_streamed;
pub mod info_vpc;
pub mod layers;
pub mod main_job;
pub mod measure;
pub mod measure_area;
pub mod parameter_flags;
pub mod pick;
pub mod profile;
pub mod region_records;
pub mod render;
pub mod render_path;
pub mod scene_args;
pub mod shared;
pub mod stream_args;
pub mod subset_args;
pub mod view;
pub mod view_args;
