//! Decodes one c-blosc 1.x frame, as OpenVDB writes them (LZ4 blocks,
//! byte shuffle): a 16-byte header, block offsets, each block in one or
//! `typesize` splits, each split raw or LZ4-compressed, then unshuffled.

/// A frame's flags.
const SHUFFLE: u8 = 0x01;
const MEMCPYED: u8 = 0x02;
const BITSHUFFLE: u8 = 0x04;
const DONT_SPLIT: u8 = 0x10;
/// The codec in bits 5-7: LZ4 is 1.
const CODEC_LZ4: u8 = 1;
const HEADER: usize = 16;

/// The frame `frame` decoded; it must hold exactly `expected` bytes.
pub(super) fn decompress(frame: &[u8], expected: usize) -> Result<Vec<u8>, String> {
    if frame.len() < HEADER {
        return Err(format!(
            "a Blosc frame of {} bytes, shorter than its header",
            frame.len()
        ));
    }
    let word = |at: usize| u32::from_le_bytes(frame[at..at + 4].try_into().expect("four bytes"));
    let flags = frame[2];
    let typesize = frame[3].max(1) as usize;
    let nbytes = word(4) as usize;
    let blocksize = word(8) as usize;
    if nbytes != expected {
        return Err(format!(
            "a Blosc frame of {nbytes} bytes where {expected} were expected"
        ));
    }
    if flags & MEMCPYED != 0 {
        return frame
            .get(HEADER..HEADER + nbytes)
            .map(<[u8]>::to_vec)
            .ok_or_else(|| "a stored Blosc frame shorter than its data".to_string());
    }
    if flags & BITSHUFFLE != 0 {
        return Err("a bit-shuffled Blosc frame (OpenVDB writes byte shuffle)".into());
    }
    if flags >> 5 != CODEC_LZ4 {
        return Err(format!(
            "a Blosc frame compressed by codec {} (OpenVDB writes LZ4, codec 1)",
            flags >> 5
        ));
    }
    if nbytes == 0 {
        return Ok(Vec::new());
    }
    if blocksize == 0 {
        return Err("a Blosc frame with blocks of 0 bytes".into());
    }
    let blocks = nbytes.div_ceil(blocksize);
    if HEADER + 4 * blocks > frame.len() {
        return Err("Blosc block offsets past the frame's end".into());
    }
    let mut out = vec![0u8; nbytes];
    for b in 0..blocks {
        let start = word(HEADER + 4 * b) as usize;
        let size = blocksize.min(nbytes - b * blocksize);
        let dest = &mut out[b * blocksize..b * blocksize + size];
        let split = flags & DONT_SPLIT == 0 && size == blocksize && typesize > 1;
        block(frame, start, dest, if split { typesize } else { 1 })?;
        if flags & SHUFFLE != 0 && typesize > 1 {
            unshuffle(dest, typesize);
        }
    }
    Ok(out)
}

/// One block at `start` into `dest`, in `splits` equal parts.
fn block(frame: &[u8], mut at: usize, dest: &mut [u8], splits: usize) -> Result<(), String> {
    let part = dest.len() / splits;
    for s in 0..splits {
        let csize = frame
            .get(at..at + 4)
            .map(|b| i32::from_le_bytes(b.try_into().expect("four bytes")))
            .ok_or("a Blosc split past the frame's end")?;
        at += 4;
        let csize = usize::try_from(csize).map_err(|_| "a Blosc split of negative size")?;
        let data = frame
            .get(at..at + csize)
            .ok_or("a Blosc split past the frame's end")?;
        at += csize;
        let out = &mut dest[s * part..(s + 1) * part];
        if csize == part {
            out.copy_from_slice(data);
        } else {
            let n = lz4_flex::block::decompress_into(data, out)
                .map_err(|e| format!("a Blosc split's LZ4 data: {e}"))?;
            if n != part {
                return Err(format!("a Blosc split gave {n} bytes, not {part}"));
            }
        }
    }
    Ok(())
}

/// Undoes byte shuffling: byte `j` of item `i` was stored at `j * items + i`;
/// the tail shorter than an item was stored as is.
fn unshuffle(block: &mut [u8], typesize: usize) {
    let items = block.len() / typesize;
    let shuffled = block[..items * typesize].to_vec();
    for i in 0..items {
        for j in 0..typesize {
            block[i * typesize + j] = shuffled[j * items + i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame as c-blosc lays it out, built here from LZ4 blocks: one
    /// block, split by byte, shuffled.
    fn frame(data: &[u8]) -> Vec<u8> {
        let ts = 4;
        let items = data.len() / ts;
        let mut shuffled = vec![0u8; data.len()];
        for i in 0..items {
            for j in 0..ts {
                shuffled[j * items + i] = data[i * ts + j];
            }
        }
        let mut body = Vec::new();
        for s in 0..ts {
            let part = &shuffled[s * items..(s + 1) * items];
            let c = lz4_flex::block::compress(part);
            body.extend_from_slice(&(c.len() as i32).to_le_bytes());
            body.extend_from_slice(&c);
        }
        let mut f = vec![2, 1, SHUFFLE | (CODEC_LZ4 << 5), ts as u8];
        f.extend_from_slice(&(data.len() as u32).to_le_bytes());
        f.extend_from_slice(&(data.len() as u32).to_le_bytes());
        f.extend_from_slice(&((HEADER + 4 + body.len()) as u32).to_le_bytes());
        f.extend_from_slice(&(HEADER as u32 + 4).to_le_bytes());
        f.extend_from_slice(&body);
        f
    }

    #[test]
    fn a_shuffled_split_frame_decodes() {
        let data: Vec<u8> = (0..512u32)
            .flat_map(|i| ((i % 7) as f32 * 0.25).to_le_bytes())
            .collect();
        assert_eq!(decompress(&frame(&data), data.len()).unwrap(), data);
        assert!(decompress(&frame(&data), data.len() + 4).is_err());
        let f = frame(&data);
        assert!(decompress(&f[..f.len() - 3], data.len()).is_err());
    }
}
