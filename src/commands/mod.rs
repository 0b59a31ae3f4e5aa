//! One module per subcommand, plus the options they share.

pub mod bench;
pub mod convert;
pub mod group;
pub mod info;
pub mod render;
pub mod shared;
pub mod view;
