//! The name of a frame's target, what plans, passes and the record of what
//! each pass was given all refer to it by. Its own module, below all three,
//! so that none of them imports another back.

/// A target, named for what it holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TargetId(pub &'static str);
