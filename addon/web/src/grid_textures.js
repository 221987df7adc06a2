// The grid on the GPU: two 3D textures, directions and colours (half floats, which WebGL2
// filters linearly everywhere), each hemisphere a block of the grid's size along x.
import * as THREE from "three";
import { HEMISPHERES } from "./irradiance_grid.js";
import { SEES_ALL } from "./visibility_volume.js";

export class GridTextures {
  constructor(grid) {
    const [nx, ny, nz] = grid.resolution;
    this.grid = grid;
    const make = () => {
      const texture = new THREE.Data3DTexture(new Uint16Array(4 * HEMISPHERES * nx * ny * nz), HEMISPHERES * nx, ny, nz);
      texture.format = THREE.RGBAFormat;
      texture.type = THREE.HalfFloatType;
      texture.minFilter = THREE.LinearFilter;
      texture.magFilter = THREE.LinearFilter;
      texture.wrapS = texture.wrapT = texture.wrapR = THREE.ClampToEdgeWrapping;
      texture.unpackAlignment = 1;
      return texture;
    };
    this.directions = make();
    this.colors = make();
    const cell = grid.cellSize();
    this.uniforms = {
      bakegiDirections: { value: this.directions },
      bakegiColors: { value: this.colors },
      bakegiBoundsMin: { value: new THREE.Vector3(...grid.boundsMin) },
      bakegiCellSize: { value: new THREE.Vector3(...cell) },
      bakegiResolution: { value: new THREE.Vector3(nx, ny, nz) },
      bakegiIndirectScale: { value: 1 },
      bakegiWhiteAlbedo: { value: 0 },
      bakegiVisibility: { value: null },
      bakegiVisibilitySize: { value: new THREE.Vector3(1, 1, 1) },
      bakegiSubdivision: { value: 1 },
      bakegiReadOffset: { value: 0 },
      bakegiReachWeight: { value: 0 },
    };
    this.setVisibility(SEES_ALL);
  }

  // The grid's visibility volume (visibility_volume.js); until it arrives every vertex is
  // read (SEES_ALL), at the fragment itself.
  setVisibility(volume, useReach = true) {
    const [sx, sy, sz] = volume.size;
    const texture = new THREE.Data3DTexture(volume.codes, sx, sy, sz);
    texture.format = THREE.RGFormat;
    texture.type = THREE.UnsignedByteType;
    texture.minFilter = texture.magFilter = THREE.NearestFilter;
    texture.unpackAlignment = 1;
    texture.needsUpdate = true;
    this.uniforms.bakegiVisibility.value?.dispose();
    this.uniforms.bakegiVisibility.value = texture;
    this.uniforms.bakegiVisibilitySize.value.set(sx, sy, sz);
    this.uniforms.bakegiSubdivision.value = volume.subdivision;
    // One subvoxel along the normal (visibility_read_offset in the core).
    const cell = this.grid.cellSize();
    this.uniforms.bakegiReadOffset.value = volume === SEES_ALL ? 0 : Math.max(...cell) / volume.subdivision;
    // With the volume, the vertices' own word too: 0 where the export's rays found a corner
    // pressed against or buried under geometry (native/src/web/corner_grid_reach.h).
    this.uniforms.bakegiReachWeight.value = volume === SEES_ALL || !useReach ? 0 : 1;
  }

  // Uploads every vertex's values (IrradianceGrid.filled()).
  upload(values) {
    const [nx, ny, nz] = this.grid.resolution;
    const directions = this.directions.image.data;
    const colors = this.colors.image.data;
    const toHalf = THREE.DataUtils.toHalfFloat;
    const width = HEMISPHERES * nx;
    for (let k = 0; k < nz; ++k) {
      for (let j = 0; j < ny; ++j) {
        for (let i = 0; i < nx; ++i) {
          const vertex = (k * ny + j) * nx + i;
          for (let h = 0; h < HEMISPHERES; ++h) {
            const texel = 4 * ((k * ny + j) * width + h * nx + i);
            const base = vertex * 6 * HEMISPHERES + 6 * h;
            for (let c = 0; c < 3; ++c) {
              directions[texel + c] = toHalf(values[base + c]);
              colors[texel + c] = toHalf(Math.min(values[base + 3 + c], 65000));
            }
            directions[texel + 3] = colors[texel + 3] = toHalf(1);
          }
        }
      }
    }
    this.directions.needsUpdate = true;
    this.colors.needsUpdate = true;
  }
}

// The paper's shader (§3.2, §3.3) added to a three.js material: indirect diffuse light =
// albedo * E / pi, E from the grid at the fragment: each axis' hemisphere on the normal's
// side, trilinearly interpolated, weighted by n_a^2, read as c (d . n). Where the visibility
// volume says the fragment's place sees all 8 vertices of its cell, the texture unit
// interpolates; where it sees some, they are fetched and their weights renormalised; where
// none, the nearest vertex it sees, or nothing (evaluate_grid_with_volume in the core);
// and then times the fragment's interpolated _BAKEGI_READS_GRID (0 at corners the export's
// rays found pressed against or buried under geometry: web/corner_grid_reach.h). The
// grid is read one subvoxel along the normal. Positions and normals are turned from glTF's
// Y-up axes to the grid's Z-up ones.
const DECLARATIONS = /* glsl */ `
uniform highp sampler3D bakegiDirections;
uniform highp sampler3D bakegiColors;
uniform highp sampler3D bakegiVisibility;
uniform vec3 bakegiBoundsMin;
uniform vec3 bakegiCellSize;
uniform vec3 bakegiResolution;
uniform vec3 bakegiVisibilitySize;
uniform float bakegiSubdivision;
uniform float bakegiReadOffset;
uniform float bakegiIndirectScale;
uniform float bakegiWhiteAlbedo;
uniform float bakegiReachWeight;
varying vec3 vBakegiWorldPosition;
varying float vBakegiReadsGrid;
vec3 bakegiGridIrradiance(vec3 p, vec3 n) {
  vec3 g = (p + bakegiReadOffset * n - bakegiBoundsMin) / bakegiCellSize - 0.5;
  ivec3 subvoxel = ivec3(clamp(floor((g + 0.5) * bakegiSubdivision), vec3(0.0), bakegiVisibilitySize - 1.0));
  ivec2 code = ivec2(texelFetch(bakegiVisibility, subvoxel, 0).rg * 255.0 + 0.5);
  g = clamp(g, vec3(0.0), bakegiResolution - 1.0);
  vec3 sum = vec3(0.0);
  if (code.x == 255) {
    for (int a = 0; a < 3; ++a) {
      float w = n[a] * n[a];
      if (w == 0.0) continue;
      float h = float(2 * a + (n[a] >= 0.0 ? 0 : 1));
      vec3 uvw = vec3((h * bakegiResolution.x + g.x + 0.5) / (6.0 * bakegiResolution.x),
                      (g.y + 0.5) / bakegiResolution.y, (g.z + 0.5) / bakegiResolution.z);
      vec3 d = texture(bakegiDirections, uvw).xyz;
      vec3 c = texture(bakegiColors, uvw).rgb;
      sum += w * c * dot(d, n);
    }
    return max(sum, vec3(0.0)) * RECIPROCAL_PI;
  }
  ivec3 lo = ivec3(min(floor(g), bakegiResolution - 2.0));
  vec3 t = g - vec3(lo);
  int mask = code.x;
  if (mask == 0) {
    if (code.y == 255) return vec3(0.0);  // sees no vertex near it: unsure, dark
    lo += ivec3(code.y & 3, (code.y >> 2) & 3, (code.y >> 4) & 3) - 1;
    mask = 1;
    t = vec3(0.0);
  }
  int width = int(bakegiResolution.x);
  for (int a = 0; a < 3; ++a) {
    float w = n[a] * n[a];
    if (w == 0.0) continue;
    int h = 2 * a + (n[a] >= 0.0 ? 0 : 1);
    vec3 d = vec3(0.0), c = vec3(0.0);
    float total = 0.0;
    for (int k = 0; k < 8; ++k) {
      if ((mask & (1 << k)) == 0) continue;
      ivec3 o = ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
      vec3 w3 = mix(1.0 - t, t, vec3(o));
      float s = max(w3.x * w3.y * w3.z, 1e-6);
      ivec3 texel = lo + o + ivec3(h * width, 0, 0);
      d += s * texelFetch(bakegiDirections, texel, 0).xyz;
      c += s * texelFetch(bakegiColors, texel, 0).rgb;
      total += s;
    }
    sum += w * (c / total) * dot(d / total, n);
  }
  return max(sum, vec3(0.0)) * RECIPROCAL_PI;
}
`;

export function addGridLighting(material, uniforms) {
  material.onBeforeCompile = (shader) => {
    Object.assign(shader.uniforms, uniforms);
    shader.vertexShader = shader.vertexShader
      .replace("#include <common>", "#include <common>\nvarying vec3 vBakegiWorldPosition;\n" +
        "attribute float bakegiReadsGrid;\nvarying float vBakegiReadsGrid;")
      .replace("#include <project_vertex>",
        "#include <project_vertex>\nvBakegiWorldPosition = (modelMatrix * vec4(transformed, 1.0)).xyz;\n" +
        "vBakegiReadsGrid = bakegiReadsGrid;");
    shader.fragmentShader = shader.fragmentShader
      .replace("#include <common>", "#include <common>\n" + DECLARATIONS)
      .replace("#include <lights_fragment_end>", `#include <lights_fragment_end>
      {
        vec3 worldNormal = inverseTransformDirection(normal, viewMatrix);
        vec3 p = vec3(vBakegiWorldPosition.x, -vBakegiWorldPosition.z, vBakegiWorldPosition.y);
        vec3 n = vec3(worldNormal.x, -worldNormal.z, worldNormal.y);
        vec3 albedo = mix(diffuseColor.rgb, vec3(1.0), bakegiWhiteAlbedo);
        float reach = mix(1.0, vBakegiReadsGrid, bakegiReachWeight);
        reflectedLight.indirectDiffuse += albedo * bakegiGridIrradiance(p, n) * reach * bakegiIndirectScale;
      }`);
  };
  material.customProgramCacheKey = () => "bakegi-grid";
}
