// Opening a folder written by bakegi web export without a server: scene.gltf, scene.bin,
// grid.bgivg and grid_visibility.bin read from the files the user picked, the whole scene at
// once.
import { IrradianceGrid } from "./irradiance_grid.js";
import { readVisibilityVolume } from "./visibility_volume.js";

function accessor(gltf, bin, index, Type) {
  const a = gltf.accessors[index];
  const view = gltf.bufferViews[a.bufferView];
  const components = { VEC3: 3, VEC2: 2 }[a.type] ?? 1;
  return new Type(bin.slice(view.byteOffset ?? 0, (view.byteOffset ?? 0) + a.count * components * 4));
}

// The primitive's arrays, as the stream would bring them all.
export function primitiveArrays(gltf, bin, description) {
  const progressive = description.extras.bakegi_progressive;
  return {
    positions: accessor(gltf, bin, description.attributes.POSITION, Float32Array),
    normals: description.attributes.NORMAL !== undefined ? accessor(gltf, bin, description.attributes.NORMAL, Float32Array) : null,
    uvs: description.attributes.TEXCOORD_0 !== undefined ? accessor(gltf, bin, description.attributes.TEXCOORD_0, Float32Array) : null,
    readsGrid: description.attributes._BAKEGI_READS_GRID !== undefined
      ? accessor(gltf, bin, description.attributes._BAKEGI_READS_GRID, Float32Array) : null,
    faces: accessor(gltf, bin, description.indices, Uint32Array),
    parent: accessor(gltf, bin, progressive.parent, Uint32Array),
  };
}

// A .bgivg file (native/src/grid/grid_file.h): the frame (8-byte magic "BAKEGI\0V", u32
// version, u32 reserved, u64 payload bytes), then bounds, resolution, encoding, valid flags
// and the hemispheres.
export function readGridFile(buffer) {
  const view = new DataView(buffer);
  const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, 6));
  if (magic !== "BAKEGI" || view.getUint8(7) !== "V".charCodeAt(0)) throw new Error("not a .bgivg grid file");
  // Version 2 keeps the sky's and emitters' light apart (a bake's own file); Export for Web
  // writes the page's grid, their sum, as version 1.
  if (view.getUint32(8, true) !== 1) {
    throw new Error("this grid file is a bake's own (version " + view.getUint32(8, true) +
      "): write the folder with Export for Web, which adds its sky and emitters' light");
  }
  let offset = 24;
  const f32 = () => { const v = view.getFloat32(offset, true); offset += 4; return v; };
  const u32 = () => { const v = view.getUint32(offset, true); offset += 4; return v; };
  const boundsMin = [f32(), f32(), f32()];
  const boundsMax = [f32(), f32(), f32()];
  const resolution = [u32(), u32(), u32()];
  const encoding = u32();
  const grid = new IrradianceGrid(resolution, boundsMin, boundsMax);
  offset += grid.count; // valid flags: every stored vertex is data (filled at bake time)
  for (let v = 0; v < grid.count; ++v) offset = grid.receive(v, view, offset, encoding);
  return grid;
}

export async function readFolder(files) {
  const byName = new Map([...files].map((f) => [f.name, f]));
  const need = (name) => {
    const file = byName.get(name);
    if (!file) throw new Error(`the folder has no ${name} (write it with bakegi web export)`);
    return file;
  };
  const gltf = JSON.parse(await need("scene.gltf").text());
  const bin = await need("scene.bin").arrayBuffer();
  const gridName = gltf.extras?.bakegi?.grid;
  const grid = gridName ? readGridFile(await need(gridName).arrayBuffer()) : null;
  const visibilityName = gltf.extras?.bakegi?.grid_visibility;
  // A promise: the viewer reads it and notes a failure instead of refusing the folder.
  const visibility = grid && visibilityName
    ? Promise.resolve(visibilityName).then((name) => need(name).arrayBuffer())
      .then((bytes) => readVisibilityVolume(bytes, grid.resolution))
    : null;
  visibility?.catch(() => {}); // handled where it is awaited
  // The images by their names, as object URLs the texture loader can read.
  const imageUrl = (name) => URL.createObjectURL(need(name));
  return { gltf, bin, grid, visibility, imageUrl };
}
