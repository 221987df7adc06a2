// The server's packets (native/cli/web_stream.h has the byte layout), read into plain
// objects the grid and the geometry apply.
export const GRID_PACKET = 1;
export const GEOMETRY_PACKET = 2;
export const VISIBILITY_PACKET = 3;

export function readPacket(buffer) {
  const view = new DataView(buffer);
  const kind = view.getUint32(0, true);
  const count = view.getUint32(4, true);
  if (kind === GRID_PACKET) {
    const encoding = view.getUint32(8, true);
    const vertices = new Uint32Array(buffer.slice(12, 12 + 4 * count));
    return { kind, encoding, vertices, view, recordsOffset: 12 + 4 * count };
  }
  if (kind === VISIBILITY_PACKET) return { kind, bytes: buffer.slice(8, 8 + count) };
  if (kind !== GEOMETRY_PACKET) throw new Error(`unknown packet kind ${kind}`);
  const entries = [];
  let offset = 8;
  for (let e = 0; e < count; ++e) {
    const [primitive, first, vertexCount, hasNormals, hasUvs, hasReadsGrid, faceCount, lookupCount] =
      [0, 1, 2, 3, 4, 5, 6, 7].map((i) => view.getUint32(offset + 4 * i, true));
    offset += 32;
    const positions = new Float32Array(buffer.slice(offset, offset + 12 * vertexCount));
    offset += 12 * vertexCount;
    let normals = null;
    if (hasNormals) {
      normals = new Float32Array(buffer.slice(offset, offset + 12 * vertexCount));
      offset += 12 * vertexCount;
    }
    let uvs = null;
    if (hasUvs) {
      uvs = new Float32Array(buffer.slice(offset, offset + 8 * vertexCount));
      offset += 8 * vertexCount;
    }
    let readsGrid = null;
    if (hasReadsGrid) {
      readsGrid = new Float32Array(buffer.slice(offset, offset + 4 * vertexCount));
      offset += 4 * vertexCount;
    }
    const faces = new Uint32Array(buffer.slice(offset, offset + 12 * faceCount));
    offset += 12 * faceCount;
    const lookups = new Uint32Array(buffer.slice(offset, offset + 8 * lookupCount));
    offset += 8 * lookupCount;
    entries.push({ primitive, first, vertexCount, positions, normals, uvs, readsGrid, faces, lookups });
  }
  if (offset !== buffer.byteLength) throw new Error("a geometry packet does not add up");
  return { kind, entries };
}
