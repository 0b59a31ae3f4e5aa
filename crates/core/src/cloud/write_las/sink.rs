//! Finishing a `las::Writer` without a panic when its file cannot be
//! written (a full disk).
//!
//! The crate's writer closes itself when it is dropped unclosed, and panics
//! if that fails ("Error when dropping the writer", las 0.11.2
//! writer/mod.rs:445). On a full disk a write failed, the writer was dropped
//! on the way out with the error, and closing it wrote again: a panic. And a
//! failed `close` leaves the writer unclosed, so its drop closes (and
//! fails) once more. Hence two things: the writer's sink is [`Fused`], which
//! after its first error lets every later write, flush and seek succeed
//! without touching the file (what is written then is thrown away with the
//! temporary file), and a writer is finished by [`close`], which always
//! closes it, returns the first error, and flushes the file itself.

use std::io::{self, BufWriter, Seek, SeekFrom, Write};

/// A sink that fails once, then succeeds at everything without doing it.
#[derive(Debug)]
pub(super) struct Fused<W> {
    inner: W,
    failed: bool,
}

impl<W> Fused<W> {
    pub(super) fn new(inner: W) -> Self {
        Self { inner, failed: false }
    }

    fn run<T>(&mut self, op: impl FnOnce(&mut W) -> io::Result<T>, dummy: T) -> io::Result<T> {
        if self.failed {
            return Ok(dummy);
        }
        let result = op(&mut self.inner);
        self.failed = result.is_err();
        result
    }
}

impl<W: Write> Write for Fused<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.run(|w| w.write(buf), buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.run(|w| w.flush(), ())
    }
}

impl<W: Seek> Seek for Fused<W> {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.run(|w| w.seek(pos), 0)
    }
}

/// Closes `writer` (headers and the LAZ chunk table written, its buffer
/// flushed) and returns the first error met, without a panic: after a
/// failed write, closing succeeds on the fused sink and the error is the
/// write's; a failed close is followed by a second one, which succeeds for
/// the same reason, so the writer's drop does nothing.
pub(super) fn close<W>(mut writer: las::Writer<Fused<BufWriter<W>>>, earlier: las::Result<()>) -> las::Result<()>
where
    W: Write + Seek + Send + Sync + 'static,
{
    let closed = writer.close();
    if closed.is_err() && writer.close().is_err() {
        // Still unclosed (an error that is not the sink's): its drop would panic.
        std::mem::forget(writer);
        return earlier.and(closed);
    }
    earlier?;
    closed?;
    let fused = writer.into_inner()?;
    if fused.failed {
        return Err(io::Error::other("a write failed").into());
    }
    fused.inner.into_inner().map_err(|e| e.into_error())?.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    /// A device that holds `room` bytes, then reports itself full.
    struct Full {
        data: Cursor<Vec<u8>>,
        room: u64,
    }

    impl Write for Full {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            if self.data.position() + buf.len() as u64 > self.room {
                return Err(io::Error::new(io::ErrorKind::StorageFull, "No space left on device"));
            }
            self.data.write(buf)
        }

        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    impl Seek for Full {
        fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
            self.data.seek(pos)
        }
    }

    /// Writes `points` points as LAS or LAZ to a device of `room` bytes, as `write_las` does.
    fn write(room: u64, compressed: bool, points: usize) -> las::Result<()> {
        let mut builder = las::Builder::from((1, 4));
        builder.point_format = las::point::Format::new(7).unwrap();
        builder.point_format.is_compressed = compressed;
        let header = builder.into_header().unwrap();
        let sink = Fused::new(BufWriter::with_capacity(512, Full { data: Cursor::new(Vec::new()), room }));
        let mut writer = las::Writer::new(sink, header)?;
        let mut written = Ok(());
        for i in 0..points {
            let point = las::Point {
                x: i as f64,
                y: (i * 7 % 13) as f64,
                z: 1.0,
                gps_time: Some(i as f64),
                color: Some(las::Color::new(1, 2, 3)),
                ..Default::default()
            };
            written = writer.write_point(point);
            if written.is_err() {
                break;
            }
        }
        close(writer, written)
    }

    #[test]
    fn a_full_device_is_an_error_not_a_panic() {
        for compressed in [false, true] {
            // Full while writing points, and full only when the header is written back at the close.
            for (room, points) in [(4096, 20_000), (400, 1)] {
                let error = write(room, compressed, points).expect_err("the device is full");
                assert!(error.to_string().contains("No space left"), "{compressed} {room}: {error}");
            }
            assert!(write(1 << 30, compressed, 1000).is_ok(), "{compressed}: with room");
        }
    }
}
