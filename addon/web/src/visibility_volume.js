// The grid's visibility volume (native/src/grid/grid_visibility_volume.h): per subvoxel (a cell
// cut into subdivision^3) the mask of its cell's 8 vertices that its points see and, where it
// sees none, the nearest vertex it does see. The export writes it as grid_visibility.bin:
// "BGIVIS1\0", u32 subdivision, u32 size[3], u32 resolution[3], u64 raw bytes, then the
// (mask, fallback) pairs as one zlib stream, which DecompressionStream("deflate") reads.

// A volume for a page without one: one subvoxel that sees all 8 vertices (the paper's
// reading everywhere).
export const SEES_ALL = { subdivision: 1, size: [1, 1, 1], codes: new Uint8Array([255, 255]) };

export async function readVisibilityVolume(buffer, resolution) {
  const view = new DataView(buffer);
  const magic = String.fromCharCode(...new Uint8Array(buffer, 0, Math.min(8, buffer.byteLength)));
  if (magic !== "BGIVIS1\0" || buffer.byteLength < 44) throw new Error("it is not a bakegi visibility volume");
  const u32 = (i) => view.getUint32(8 + 4 * i, true);
  const subdivision = u32(0);
  const size = [u32(1), u32(2), u32(3)];
  const forGrid = [u32(4), u32(5), u32(6)];
  if (forGrid.some((r, a) => r !== resolution[a] || size[a] !== r * subdivision)) {
    throw new Error("it was made for another grid");
  }
  const raw = Number(view.getBigUint64(36, true));
  if (raw !== 2 * size[0] * size[1] * size[2]) throw new Error("corrupt: its size does not match its subvoxels");
  const stream = new Blob([new Uint8Array(buffer, 44)]).stream().pipeThrough(new DecompressionStream("deflate"));
  let codes;
  try {
    codes = new Uint8Array(await new Response(stream).arrayBuffer());
  } catch {
    throw new Error("corrupt: its codes do not inflate");
  }
  if (codes.length !== raw) throw new Error("corrupt: its size does not match its subvoxels");
  return { subdivision, size, codes };
}
