//! Writing the images: one `frame_NNNNNN.png` per snapshot and, streamed beside them, one
//! animated PNG (APNG: every browser and most viewers play it; still viewers show frame 0).

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

pub struct FrameWriter {
    out: PathBuf,
    width: u32,
    height: u32,
    frames: Vec<PathBuf>,
    animation: Option<(PathBuf, png::Writer<BufWriter<File>>)>,
}

fn encoder<W: std::io::Write>(w: W, width: u32, height: u32) -> png::Encoder<'static, W> {
    let mut e = png::Encoder::new(w, width, height);
    e.set_color(png::ColorType::Rgba);
    e.set_depth(png::BitDepth::Eight);
    e.set_compression(png::Compression::High);
    e
}

/// One still image.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), String> {
    let file = File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut writer = encoder(BufWriter::new(file), width, height).write_header().map_err(|e| format!("{}: {e}", path.display()))?;
    writer.write_image_data(rgba).map_err(|e| format!("{}: {e}", path.display()))?;
    writer.finish().map_err(|e| format!("{}: {e}", path.display()))
}

impl FrameWriter {
    /// Frames go into `out`; with `animation_frames` > 0 also `out/animation.png` at `fps`.
    pub fn new(out: &Path, width: u32, height: u32, animation_frames: usize, fps: u16) -> Result<FrameWriter, String> {
        let animation = if animation_frames > 0 {
            let path = out.join("animation.png");
            let file = File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            let mut e = encoder(BufWriter::new(file), width, height);
            let err = |e: png::EncodingError| format!("{}: {e}", path.display());
            e.set_animated(animation_frames as u32, 0).map_err(err)?;
            e.set_frame_delay(1, fps.max(1)).map_err(err)?;
            let writer = e.write_header().map_err(err)?;
            Some((path, writer))
        } else {
            None
        };
        Ok(FrameWriter { out: out.to_path_buf(), width, height, frames: Vec::new(), animation })
    }

    /// Writes snapshot `index`'s image.
    pub fn frame(&mut self, index: usize, rgba: &[u8]) -> Result<(), String> {
        let path = self.out.join(format!("frame_{index:06}.png"));
        write_png(&path, self.width, self.height, rgba)?;
        self.frames.push(path);
        if let Some((path, writer)) = &mut self.animation {
            writer.write_image_data(rgba).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        Ok(())
    }

    /// The frames written and the finished animation.
    pub fn finish(self) -> Result<(Vec<PathBuf>, Option<PathBuf>), String> {
        let animation = match self.animation {
            Some((path, writer)) => {
                writer.finish().map_err(|e| format!("{}: {e}", path.display()))?;
                Some(path)
            }
            None => None,
        };
        Ok((self.frames, animation))
    }
}
