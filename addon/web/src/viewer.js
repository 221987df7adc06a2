// The bakegi web page (issue 16, §4 of Pacanowski et al. 2008): served by `bakegi serve`, it
// asks for the scene's packets one after the other, grid and geometry interleaved, and draws
// after each: direct light computed here (three.js lights), indirect light from the grid
// (grid_textures.js), the grid's missing vertices filled by push-pull after every grid packet
// (Fig. 2). Opened from a folder (no server) it reads the files the user picks instead.
// Query: ?until=F stops after F of the stream's bytes (0..1); ?vectors=V&vertices=N&
// encoding=quantized|factored choose the packets; ?only=grid streams the grid alone; ?size=
// WxH fixes the canvas; ?mode=full|indirect|direct|light (light: the grid's value E/pi on
// white, what Blender shows of the BakeGI_Indirect attribute); ?visibility=0 reads the grid
// the paper's way (no visibility volume), ?reach=0 ignores the vertices' _BAKEGI_READS_GRID
// (both to compare). window.bakegiState tells
// tests and people where it stands.
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { areaLightShadows, lightingNotes, shadowedAreaLightCount, makeCamera, makeLights, makeMaterial, primitivesOf, setTextureListener, texturesSettled } from "./gltf_scene.js";
import { addGridLighting, GridTextures } from "./grid_textures.js";
import { IrradianceGrid } from "./irradiance_grid.js";
import { GEOMETRY_PACKET, GRID_PACKET, readPacket, VISIBILITY_PACKET } from "./packets.js";
import { readVisibilityVolume } from "./visibility_volume.js";
import { primitiveArrays, readFolder } from "./local_folder.js";
import { ProgressiveGeometry } from "./progressive_geometry.js";

const query = new URLSearchParams(location.search);
const state = (window.bakegiState = {
  phase: "starting", packets: 0, packetCount: 0, bytes: 0, totalBytes: 0, gridFraction: 0,
  geometryFraction: 0, firstImageMs: null, doneMs: null, error: null, frames: 0,
  notes: [], hasVisibility: false, pushPullMs: 0, fetchMs: 0, decodeMs: 0, uploadMs: 0, renderMs: 0, timeline: { script: performance.now() },
});

// The stream's first requests were started by index.html before this script arrived
// (window.bakegiEarly); without it (a page of its own), the manifest is asked for here.
const early = window.bakegiEarly ?? {
  suffix: "",
  manifest: location.protocol.startsWith("http")
    ? fetch("stream/manifest.json").then((r) => (r.ok ? r.json() : null)).catch(() => null)
    : Promise.resolve(null),
  gltf: null,
};
const suffix = early.suffix;
// ?visibility=0: the paper's reading, through walls (to compare; the test does).
const useVisibility = query.get("visibility") !== "0";
const useReach = query.get("reach") !== "0";

const canvas = document.getElementById("view");
const status = document.getElementById("status");
state.timeline.context = performance.now();
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
state.timeline.context = performance.now() - state.timeline.context;
renderer.outputColorSpace = THREE.SRGBColorSpace; // Blender's "Standard" view transform
// Direct light is shadowed (point, spot and sun lights; gltf_scene.js), as the bake's is.
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;
renderer.toneMapping = THREE.NoToneMapping;
const size = query.get("size")?.split("x").map(Number);
function resize() {
  const [w, h] = size ?? [innerWidth, innerHeight];
  // Setting a canvas' size, even to its own, clears its drawing buffer: only when it changed.
  const ratio = size ? 1 : devicePixelRatio;
  const sized = canvas.width === Math.floor(w * ratio) && canvas.height === Math.floor(h * ratio);
  if (!sized || renderer.getPixelRatio() !== ratio || renderer.getSize(new THREE.Vector2()).x !== w) {
    renderer.setPixelRatio(ratio);
    renderer.setSize(w, h, !size);
  }
  if (size) Object.assign(canvas.style, { width: `${w}px`, height: `${h}px` });
  if (view.camera) {
    view.camera.aspect = w / h;
    view.camera.updateProjectionMatrix();
  }
}

const view = (window.bakegiView = { scene: new THREE.Scene(), camera: null, controls: null, lights: [], textures: null, grid: null, geometries: [], materials: [] });

function render() {
  if (!view.camera) return;
  const start = performance.now();
  renderer.render(view.scene, view.camera);
  state.renderMs += performance.now() - start;
  ++state.frames;
  if (state.firstImageMs === null && state.geometryFraction > 0 && (!view.grid || state.gridFraction > 0)) {
    state.firstImageMs = performance.now();
  }
}

// A draw at the next animation frame, one for however many asks come before it: packets,
// textures and camera moves can arrive faster than a frame is drawn (software WebGL draws
// Sponza in about a second), and drawing each would hold the stream back.
let drawPending = false;
function requestRender() {
  if (drawPending) return;
  drawPending = true;
  requestAnimationFrame(() => {
    drawPending = false;
    render();
  });
}

function setMode(mode) {
  const indirectOnly = mode === "indirect" || mode === "light";
  for (const light of view.lights) light.visible = !indirectOnly;
  for (const material of view.materials) {
    material.emissiveIntensity = mode === "light" ? 0 : material.userData.emission;
  }
  if (view.textures) {
    view.textures.uniforms.bakegiIndirectScale.value = mode === "direct" ? 0 : 1;
    view.textures.uniforms.bakegiWhiteAlbedo.value = mode === "light" ? 1 : 0;
  }
  render();
}

function showProgress() {
  document.getElementById("grid-progress").value = state.gridFraction;
  document.getElementById("geometry-progress").value = state.geometryFraction;
  const mb = (b) => (b / 1e6).toFixed(2);
  status.textContent = state.error ? `error: ${state.error}` :
    `${state.phase}: ${mb(state.bytes)} of ${mb(state.totalBytes)} MB, grid ` +
    `${(100 * state.gridFraction).toFixed(0)}%, geometry ${(100 * state.geometryFraction).toFixed(0)}%` +
    (state.firstImageMs !== null ? `; first image ${state.firstImageMs.toFixed(0)} ms` : "") +
    (state.doneMs !== null ? `, all ${state.doneMs.toFixed(0)} ms` : "") +
    state.notes.map((note) => `. Note: ${note}`).join("");
}

// The grid carries the sky's and emitters' direct light too: its views are not "indirect".
function nameModesForEmittedLight() {
  const names = { indirect: "grid only (bounced light, sky, emitters)", direct: "lamps only",
    light: "grid light (E/&pi;, bounced + sky + emitters)" };
  for (const option of document.getElementById("mode").options) {
    if (names[option.value]) option.innerHTML = names[option.value];
  }
}

function shadowed(mesh) {
  mesh.receiveShadow = true;
  mesh.castShadow = mesh.material.userData.castsShadow !== false; // glass and veils cast none
  return mesh;
}

// The scene's fixed parts from the glTF: materials, lights, camera, one mesh per primitive.
function buildScene(gltf, grid, primitiveInfo, imageUrl = (uri) => uri) {
  state.notes = lightingNotes(gltf);
  if (grid && gltf.extras?.bakegi?.grid_has_emitted_light) nameModesForEmittedLight();
  view.grid = grid;
  view.textures = grid ? new GridTextures(grid) : null;
  setTextureListener(requestRender);
  // Every material, the default one of a primitive without any too, takes the grid's light
  // and the area lights' shadows.
  const areaShadows = shadowedAreaLightCount(gltf);
  const lit = (description) => {
    const material = makeMaterial(description, gltf, imageUrl);
    if (view.textures) addGridLighting(material, view.textures.uniforms);
    areaLightShadows(material, areaShadows);
    return material;
  };
  const materials = (gltf.materials ?? []).map(lit);
  const keep = (material) => {
    material.userData.emission = material.emissiveIntensity;
    view.materials.push(material);
    return material;
  };
  primitivesOf(gltf).forEach((p, i) => {
    const info = primitiveInfo[i];
    const geometry = new ProgressiveGeometry(info.vertex_count, info.face_count, info.has_normals, info.has_uvs);
    const material = materials[p.description.material] ?? lit({});
    if (!info.has_normals) {
      // No NORMAL: flat shading, as glTF asks (a material per primitive so that smooth
      // primitives of the same material are not made flat).
      const flat = material.clone();
      flat.flatShading = true;
      flat.onBeforeCompile = material.onBeforeCompile;
      flat.customProgramCacheKey = material.customProgramCacheKey;
      view.scene.add(shadowed(new THREE.Mesh(geometry.geometry, keep(flat))));
    } else {
      view.scene.add(shadowed(new THREE.Mesh(geometry.geometry, keep(material))));
    }
    view.geometries.push(geometry);
  });
  view.lights = makeLights(gltf);
  for (const light of view.lights) view.scene.add(light);
  const [w, h] = size ?? [innerWidth, innerHeight];
  view.camera = makeCamera(gltf, w / h);
  if (!view.camera) {
    view.camera = new THREE.PerspectiveCamera(40, w / h, 0.01, 1000);
    view.camera.position.set(0, 1, 4);
  }
  // The orbit's centre ahead of the camera (taken before OrbitControls, which looks at the
  // origin when made).
  const forward = new THREE.Vector3(0, 0, -1).applyQuaternion(view.camera.quaternion);
  const target = view.camera.position.clone().addScaledVector(forward, 3);
  view.controls = new OrbitControls(view.camera, canvas);
  view.controls.target.copy(target);
  view.controls.update();
  view.controls.addEventListener("change", requestRender);
  resize();
  document.getElementById("mode").value = query.get("mode") ?? "full";
  setMode(query.get("mode") ?? "full");
}

function refreshGrid() {
  if (!view.grid) return;
  const start = performance.now();
  const values = view.grid.filled(document.getElementById("push-pull").checked);
  const filled = performance.now();
  view.textures.upload(values);
  state.pushPullMs += filled - start;
  state.uploadMs += performance.now() - filled;
  state.gridFraction = view.grid.fraction();
}

function refreshGeometry() {
  let received = 0;
  let total = 0;
  for (const g of view.geometries) {
    g.update();
    received += g.received;
    total += g.vertexCount;
  }
  state.geometryFraction = total ? received / total : 1;
}

// The grid's visibility volume (a promise of it, or a function giving one); one that cannot
// be read leaves the page reading the grid the paper's way, and says so.
async function applyVisibility(volume) {
  try {
    view.textures.setVisibility(await (typeof volume === "function" ? volume() : volume), useReach);
    state.hasVisibility = true;
  } catch (error) {
    state.notes.push(`the grid's visibility volume could not be read (${error.message}): ` +
      "its light may pass through thin walls");
  }
}

async function fetchBytes(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: ${response.status} ${await response.text()}`);
  return response.arrayBuffer();
}

async function stream(manifest) {
  const gltf = (early.gltf?.url === manifest.gltf && (await early.gltf.json)) || (await (await fetch(manifest.gltf)).json());
  state.timeline.manifest = performance.now();
  state.packetCount = manifest.packets.length;
  state.totalBytes = manifest.total_bytes;
  const until = Number(query.get("until") ?? 1);
  const gridOnly = query.get("only") === "grid";
  if (gridOnly) state.totalBytes = manifest.packets.filter((p) => p.kind === "grid").reduce((a, p) => a + p.bytes, 0);
  // The packets this page asks for, in the stream's order.
  const wanted = [];
  let planned = 0;
  for (let k = 0; k < manifest.packets.length; ++k) {
    if (gridOnly && manifest.packets[k].kind !== "grid") continue;
    if (planned + manifest.packets[k].bytes > until * state.totalBytes + 0.5) break;
    planned += manifest.packets[k].bytes;
    wanted.push(k);
  }
  // Requests run ahead: the first two while the scene is built, then the next while this one
  // is decoded, so that the page never waits on a round trip.
  const requests = [];
  const request = (i) => {
    if (i >= wanted.length || requests[i]) return;
    requests[i] = fetchBytes(`stream/packet/${wanted[i]}${suffix}`);
    requests[i].catch(() => {}); // a failure is reported where it is awaited
  };
  request(0);
  request(1);
  const g = manifest.grid;
  buildScene(gltf, g ? new IrradianceGrid(g.resolution, g.bounds_min, g.bounds_max) : null, manifest.primitives);
  state.timeline.built = performance.now();
  state.phase = "streaming";
  state.startMs = performance.now();
  for (let i = 0; i < wanted.length; ++i) {
    const k = wanted[i];
    const fetchStart = performance.now();
    const bytes = await requests[i];
    requests[i] = null;
    request(i + 1);
    state.fetchMs += performance.now() - fetchStart;
    const packet = readPacket(bytes);
    state.bytes += manifest.packets[k].bytes;
    ++state.packets;
    if (packet.kind === GRID_PACKET) {
      const record = packet.encoding === 1 ? 42 : 144;
      const decodeStart = performance.now();
      packet.vertices.forEach((v, j) => view.grid.receive(v, packet.view, packet.recordsOffset + j * record, packet.encoding));
      state.decodeMs += performance.now() - decodeStart;
      refreshGrid();
    } else if (packet.kind === VISIBILITY_PACKET) {
      if (useVisibility) await applyVisibility(() => readVisibilityVolume(packet.bytes, view.grid.resolution));
    } else if (packet.kind === GEOMETRY_PACKET) {
      for (const entry of packet.entries) view.geometries[entry.primitive].add(entry);
      refreshGeometry();
    }
    // The first lit image is drawn at once, later ones at the next animation frame.
    const firstLit = state.firstImageMs === null && state.geometryFraction > 0 && (!view.grid || state.gridFraction > 0);
    if (firstLit) render();
    else requestRender();
    showProgress();
  }
  await texturesSettled();
  render(); // the image of everything received, textures too, before the phase says so
  state.phase = state.bytes >= state.totalBytes ? "done" : "paused";
  state.doneMs = performance.now();
  showProgress();
}

async function openFolder(files) {
  const { gltf, bin, grid, visibility, imageUrl } = await readFolder(files);
  const prims = primitivesOf(gltf);
  const info = prims.map((p) => {
    const arrays = primitiveArrays(gltf, bin, p.description);
    return { arrays, vertex_count: arrays.positions.length / 3, face_count: arrays.faces.length / 3,
      has_normals: !!arrays.normals, has_uvs: !!arrays.uvs };
  });
  buildScene(gltf, grid, info, imageUrl);
  if (visibility && useVisibility) await applyVisibility(visibility);
  view.geometries.forEach((g, i) => {
    const a = info[i].arrays;
    g.setAll(a.positions, a.normals, a.uvs, a.readsGrid, a.faces, a.parent);
  });
  refreshGrid();
  refreshGeometry();
  render();
  state.firstImageMs ??= performance.now();
  await texturesSettled();
  render();
  state.phase = "done";
  state.doneMs = performance.now();
  showProgress();
}

if (query.get("panel") === "0") document.getElementById("panel").style.display = "none";
if (query.get("pushpull") === "0") document.getElementById("push-pull").checked = false;
document.getElementById("mode").addEventListener("change", (e) => setMode(e.target.value));
document.getElementById("push-pull").addEventListener("change", () => { refreshGrid(); requestRender(); });
addEventListener("resize", () => { resize(); requestRender(); });

async function main() {
  const manifest = await early.manifest;
  if (manifest) return stream(manifest);
  document.body.classList.add("local");
  state.phase = "waiting for a folder";
  showProgress();
  document.getElementById("folder").addEventListener("change", (e) =>
    openFolder(e.target.files).catch(fail));
}

function fail(error) {
  state.error = String(error?.message ?? error);
  state.phase = "failed";
  showProgress();
  console.error(error);
}

main().catch(fail);
