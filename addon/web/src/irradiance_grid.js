// The Irradiance Vector Grid on the page (Pacanowski et al. 2008, §3.3, §4.1): vertices arrive
// in any order (the server's stream, or a whole .bgivg file), each as six hemispheres of a
// direction d and a colour c (I^k = c_k d); the vertices not yet received are filled by a
// 3D push-pull with the pyramid filter (a mirror of native/src/grid/grid_push_pull.cpp, on
// d and c instead of the 3x3 matrices), then the grid goes to the GPU as two 3D textures:
// directions and colours, the six hemispheres side by side along x (+x -x +y -y +z -z).

export const HEMISPHERES = 6;
const VALUES = HEMISPHERES * 6; // per vertex: per hemisphere d.xyz then c.rgb
export const QUANTIZED = 1;
export const FACTORED = 2;
export const FLOAT_MATRICES = 0;

// Shared-exponent RGB (GL_EXT_texture_shared_exponent): 9-bit mantissas, exponent bias 15.
export function decodeRgb9e5(packed) {
  const scale = Math.pow(2, (packed >>> 27) - 15 - 9);
  return [(packed & 511) * scale, ((packed >>> 9) & 511) * scale, ((packed >>> 18) & 511) * scale];
}

// A direction on 8 bits per coordinate: (x + 1) * 127.5; renormalized, zero as +z.
export function decodeDirection(x, y, z) {
  const d = [x / 127.5 - 1, y / 127.5 - 1, z / 127.5 - 1];
  const length = Math.hypot(d[0], d[1], d[2]);
  return length > 0 ? d.map((v) => v / length) : [0, 0, 1];
}

function hemisphereAxis(h) {
  const axis = [0, 0, 0];
  axis[h >> 1] = h & 1 ? -1 : 1;
  return axis;
}

// A 3x3 matrix (columns I^R, I^G, I^B) factored as the core does (grid_quantization.cpp).
export function factorMatrix(m, h) {
  const axis = hemisphereAxis(h);
  const sum = [0, 1, 2].map((e) => m[e] + m[3 + e] + m[6 + e]);
  const length = Math.hypot(sum[0], sum[1], sum[2]);
  let d = length > 0 ? sum.map((v) => v / length) : axis;
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  if (dot(d, axis) < 0.05) d = axis;
  const along = dot(d, axis);
  const c = [0, 1, 2].map((k) => Math.max(0, dot(m.slice(3 * k, 3 * k + 3), axis) / along));
  return [d, c];
}

export class IrradianceGrid {
  constructor(resolution, boundsMin, boundsMax) {
    this.resolution = resolution;
    this.boundsMin = boundsMin;
    this.boundsMax = boundsMax;
    this.count = resolution[0] * resolution[1] * resolution[2];
    this.values = new Float32Array(this.count * VALUES);
    this.known = new Uint8Array(this.count);
    this.received = 0;
  }

  cellSize() {
    return [0, 1, 2].map((a) => (this.boundsMax[a] - this.boundsMin[a]) / this.resolution[a]);
  }

  fraction() {
    return this.received / this.count;
  }

  // One vertex's hemispheres from `bytes` (a DataView) at `offset`; returns the next offset.
  receive(vertex, view, offset, encoding) {
    const out = vertex * VALUES;
    for (let h = 0; h < HEMISPHERES; ++h) {
      let d, c;
      if (encoding === QUANTIZED) {
        d = decodeDirection(view.getUint8(offset), view.getUint8(offset + 1), view.getUint8(offset + 2));
        c = decodeRgb9e5(view.getUint32(offset + 3, true));
        offset += 7;
      } else if (encoding === FACTORED) {
        const f = [0, 1, 2, 3, 4, 5].map((i) => view.getFloat32(offset + 4 * i, true));
        d = f.slice(0, 3);
        c = f.slice(3);
        offset += 24;
      } else {
        const m = [0, 1, 2, 3, 4, 5, 6, 7, 8].map((i) => view.getFloat32(offset + 4 * i, true));
        [d, c] = factorMatrix(m, h);
        offset += 36;
      }
      this.values.set(d, out + 6 * h);
      this.values.set(c, out + 6 * h + 3);
    }
    if (!this.known[vertex]) {
      this.known[vertex] = 1;
      ++this.received;
    }
    return offset;
  }

  // Every vertex: the received ones as they are, the others filled by push-pull (or left
  // at zero without it).
  filled(pushPullOn = true) {
    if (!pushPullOn || this.received === this.count || this.received === 0) return this.values;
    return pushPull(this.values, this.known, this.resolution);
  }
}

// Cell-centred levels: coarse vertex c sits between fine 2c and 2c + 1; the tent over fine
// 2c - 1 .. 2c + 2 weighs 1, 3, 3, 1 (the pyramid filter applied at each push step).
const TENT = [1, 3, 3, 1];

function push(fine) {
  const n = fine.n.map((v) => Math.max(1, (v + 1) >> 1));
  const count = n[0] * n[1] * n[2];
  const values = new Float32Array(count * VALUES);
  const weight = new Float32Array(count);
  for (let k = 0; k < n[2]; ++k) {
    for (let j = 0; j < n[1]; ++j) {
      for (let i = 0; i < n[0]; ++i) {
        const c = (k * n[1] + j) * n[0] + i;
        let total = 0;
        let filterTotal = 0;
        for (let dk = 0; dk < 4; ++dk) {
          const fk = 2 * k - 1 + dk;
          if (fk < 0 || fk >= fine.n[2]) continue;
          for (let dj = 0; dj < 4; ++dj) {
            const fj = 2 * j - 1 + dj;
            if (fj < 0 || fj >= fine.n[1]) continue;
            for (let di = 0; di < 4; ++di) {
              const fi = 2 * i - 1 + di;
              if (fi < 0 || fi >= fine.n[0]) continue;
              const filter = TENT[di] * TENT[dj] * TENT[dk];
              filterTotal += filter;
              const f = (fk * fine.n[1] + fj) * fine.n[0] + fi;
              const w = filter * fine.weight[f];
              if (w === 0) continue;
              total += w;
              for (let v = 0; v < VALUES; ++v) values[c * VALUES + v] += w * fine.values[f * VALUES + v];
            }
          }
        }
        if (total > 0) {
          for (let v = 0; v < VALUES; ++v) values[c * VALUES + v] /= total;
          weight[c] = Math.min(1, (total / filterTotal) * 8);
        }
      }
    }
  }
  return { n, values, weight };
}

function pull(fine, coarse) {
  const blended = new Float32Array(VALUES);
  for (let k = 0; k < fine.n[2]; ++k) {
    for (let j = 0; j < fine.n[1]; ++j) {
      for (let i = 0; i < fine.n[0]; ++i) {
        const f = (k * fine.n[1] + j) * fine.n[0] + i;
        const own = fine.weight[f];
        if (own >= 1) continue;
        const fc = [i, j, k];
        const lo = [0, 0, 0];
        const hi = [0, 0, 0];
        const t = [0, 0, 0];
        for (let a = 0; a < 3; ++a) {
          const x = Math.min(Math.max((fc[a] - 0.5) * 0.5, 0), coarse.n[a] - 1);
          lo[a] = Math.floor(x);
          hi[a] = Math.min(lo[a] + 1, coarse.n[a] - 1);
          t[a] = x - lo[a];
        }
        blended.fill(0);
        for (let corner = 0; corner < 8; ++corner) {
          const ci = corner & 1 ? hi[0] : lo[0];
          const cj = corner & 2 ? hi[1] : lo[1];
          const ck = corner & 4 ? hi[2] : lo[2];
          const w = (corner & 1 ? t[0] : 1 - t[0]) * (corner & 2 ? t[1] : 1 - t[1]) * (corner & 4 ? t[2] : 1 - t[2]);
          if (w === 0) continue;
          const base = ((ck * coarse.n[1] + cj) * coarse.n[0] + ci) * VALUES;
          for (let v = 0; v < VALUES; ++v) blended[v] += w * coarse.values[base + v];
        }
        for (let v = 0; v < VALUES; ++v) {
          fine.values[f * VALUES + v] = own * fine.values[f * VALUES + v] + (1 - own) * blended[v];
        }
        fine.weight[f] = 1;
      }
    }
  }
}

// Fills the vertices not known from the known ones; known ones are never changed.
export function pushPull(values, known, resolution) {
  const levels = [{ n: resolution.slice(), values: Float32Array.from(values), weight: Float32Array.from(known) }];
  while (levels[levels.length - 1].n.some((v) => v > 1)) levels.push(push(levels[levels.length - 1]));
  levels[levels.length - 1].weight.fill(1);
  for (let l = levels.length - 2; l >= 0; --l) pull(levels[l], levels[l + 1]);
  return levels[0].values;
}
