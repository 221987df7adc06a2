// What the page takes from scene.gltf (written by bakegi web export): materials (base colour,
// emission as radiance), lights (KHR_lights_punctual in the core's units, which three.js'
// physically based lights read the same way: W/sr, W/m^2, with shadow maps; area lights from
// the extras as RectAreaLights of that radiance, unshadowed), the camera, and each
// primitive's progressive data.
import * as THREE from "three";
import { RectAreaLightUniformsLib } from "three/examples/jsm/lights/RectAreaLightUniformsLib.js";

// imageUrl(uri): where the page finds an image the glTF names (beside it on the server, an
// object URL for a picked folder).
export function makeMaterial(description, gltf = {}, imageUrl = (uri) => uri) {
  const base = description.pbrMetallicRoughness?.baseColorFactor ?? [0.8, 0.8, 0.8, 1];
  const textureIndex = description.pbrMetallicRoughness?.baseColorTexture?.index;
  // glTF base colour textures are sRGB.
  const map = textureIndex === undefined ? null : loadTexture(gltf, textureIndex, imageUrl, THREE.SRGBColorSpace);
  const radiance = description.extras?.emission_radiance ?? [0, 0, 0];
  const peak = Math.max(...radiance);
  // See-through surfaces (the export's see_through extras): a cut-out's alpha map (opacity x
  // its texture, linear), tested at 0.5 as its holes are 0 and its leaves 1 (three.js' shadow
  // maps test it too); a share passing everywhere (glass, a veil) drawn that transparent, and
  // casting no shadow where it passes most light.
  const seeThrough = description.extras?.see_through;
  const alphaIndex = seeThrough?.opacity_texture;
  const alphaMap = alphaIndex === undefined ? null : loadTexture(gltf, alphaIndex, imageUrl, THREE.NoColorSpace);
  const opacity = seeThrough ? (alphaMap ? 1 : seeThrough.opacity) * (1 - seeThrough.transmission) : 1;
  const transparent = opacity < 1;
  // Lambert only (specularIntensity 0), as the core's diffuse materials; the colours are
  // linear, as glTF's factors.
  const material = new THREE.MeshPhysicalMaterial({
    color: new THREE.Color(base[0], base[1], base[2]),
    map,
    roughness: 1,
    metalness: 0,
    specularIntensity: 0,
    emissive: peak > 0 ? new THREE.Color(radiance[0] / peak, radiance[1] / peak, radiance[2] / peak) : new THREE.Color(0, 0, 0),
    emissiveIntensity: peak,
    // Both sides, as Blender draws and bakes them (backface culling off by default).
    side: THREE.DoubleSide,
    alphaMap,
    alphaTest: alphaMap ? 0.5 : 0,
    transparent,
    opacity,
    depthWrite: !transparent,
  });
  material.userData.castsShadow = opacity >= 0.5;
  return material;
}

// glTF texture `index` as a three.js texture of `colorSpace`, repeating, v down; the page
// waits for it (pendingTextures) before it says it is done.
function loadTexture(gltf, index, imageUrl, colorSpace) {
  const image = gltf.images[gltf.textures[index].source];
  let settle;
  pendingTextures.push(new Promise((resolve) => (settle = resolve)));
  // A texture that fails to load leaves the material as it was before the texture came.
  const texture = new THREE.TextureLoader().load(imageUrl(image.uri), () => { onTextureLoaded(); settle(); }, undefined, settle);
  texture.colorSpace = colorSpace;
  texture.flipY = false; // glTF's v runs down the image
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  return texture;
}

function nodeTransform(object, node) {
  if (node.translation) object.position.fromArray(node.translation);
  if (node.rotation) object.quaternion.fromArray(node.rotation);
}

// The scene's bounds from its POSITION accessors' min and max (glTF requires them), for the
// shadow cameras: [centre, radius], or null when no accessor has them.
export function sceneBounds(gltf) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (const mesh of gltf.meshes ?? []) {
    for (const primitive of mesh.primitives) {
      const accessor = gltf.accessors?.[primitive.attributes?.POSITION];
      if (!accessor?.min || !accessor?.max) continue;
      for (let a = 0; a < 3; ++a) {
        lo[a] = Math.min(lo[a], accessor.min[a]);
        hi[a] = Math.max(hi[a], accessor.max[a]);
      }
    }
  }
  if (!(lo[0] <= hi[0])) return null;
  const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  const radius = Math.max(1e-3, 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
  return [centre, radius];
}

// Shadow maps for a point, spot or sun light (three.js has none for RectAreaLights): its
// camera spans the scene's bounds, and the biases scale with them (self-shadowing acne on
// one side, light leaking under contact on the other).
function castShadows(light, holder, bounds) {
  if (!bounds) return;
  const [centre, radius] = bounds;
  light.castShadow = true;
  light.shadow.mapSize.set(1024, 1024);
  // The depth bias is a fraction of the shadow camera's depth range, which spans the bounds
  // as the map's texels do, so it stays about three texels deep at any scene size: 0.0005
  // left acne stripes on a floor under a 45-degree sun (software WebGL's depth maps).
  light.shadow.bias = -0.002;
  light.shadow.normalBias = 0.004 * radius;
  const camera = light.shadow.camera;
  if (light.isDirectionalLight) {
    // A sun has no position: stand it off the bounds along its direction so that its
    // orthographic camera sees all of them.
    const direction = new THREE.Vector3(0, 0, -1).applyQuaternion(holder.quaternion);
    holder.position.copy(centre).addScaledVector(direction, -2 * radius);
    Object.assign(camera, { left: -radius, right: radius, top: radius, bottom: -radius, near: 0.5 * radius, far: 3.5 * radius });
  } else {
    const reach = holder.position.distanceTo(centre) + radius;
    camera.near = Math.max(1e-3 * radius, 0.01);
    camera.far = 1.1 * reach;
  }
  camera.updateProjectionMatrix();
}

// How the page draws light the glTF's lamps do not carry (the sky's, emitters'): the notes the
// exporter wrote (native/src/web/gltf_export.cpp), which Export for Web returns as warnings.
export function lightingNotes(gltf) {
  return gltf.extras?.bakegi?.notes ?? [];
}

export function makeLights(gltf) {
  const lights = [];
  const bounds = sceneBounds(gltf);
  const punctual = gltf.extensions?.KHR_lights_punctual?.lights ?? [];
  for (const node of gltf.nodes ?? []) {
    const index = node.extensions?.KHR_lights_punctual?.light;
    if (index === undefined) continue;
    const l = punctual[index];
    const color = new THREE.Color(...(l.color ?? [1, 1, 1]));
    let light;
    if (l.type === "point") {
      light = new THREE.PointLight(color, l.intensity, 0, 2);
    } else if (l.type === "spot") {
      const outer = l.spot?.outerConeAngle ?? Math.PI / 4;
      const inner = l.spot?.innerConeAngle ?? 0;
      light = new THREE.SpotLight(color, l.intensity, 0, outer, 1 - inner / outer, 2);
    } else {
      light = new THREE.DirectionalLight(color, l.intensity);
    }
    // three.js puts spot and sun lights at (0, 1, 0) of their parent; glTF's light is at
    // its node's origin (left there, a sun shone 45 degrees off its direction).
    light.position.set(0, 0, 0);
    const holder = new THREE.Object3D();
    nodeTransform(holder, node);
    holder.add(light);
    if (light.target) {
      // three.js aims spot and sun lights at a target; glTF's look down the node's -Z.
      light.target.position.set(0, 0, -1);
      holder.add(light.target);
    }
    // Cast Shadow off in Blender: nothing blocks this lamp's light (the exporter's extras).
    if (l.extras?.cast_shadow !== false) castShadows(light, holder, bounds);
    lights.push(holder);
  }
  // The shadow-casting area lights first: area light i's shading reads proxy i's shadow map.
  const areas = [...(gltf.extras?.bakegi?.area_lights ?? [])]
    .sort((a, b) => areaCastsShadow(b) - areaCastsShadow(a));
  if (areas.length) RectAreaLightUniformsLib.init();
  const proxies = [];
  const shadowed = bounds ? shadowedAreaLightCount(gltf) : 0;
  for (const a of areas) {
    const peak = Math.max(...a.radiance);
    if (!(peak > 0)) continue;
    const color = new THREE.Color(a.radiance[0] / peak, a.radiance[1] / peak, a.radiance[2] / peak);
    const light = new THREE.RectAreaLight(color, peak, a.size_x, a.size_y);
    light.position.fromArray(a.position);
    // A RectAreaLight shines down its -Z with its width along its X: build that frame.
    const z = new THREE.Vector3(...a.direction).negate().normalize();
    const x = new THREE.Vector3(...a.axis_u).normalize();
    const y = new THREE.Vector3().crossVectors(z, x);
    light.quaternion.setFromRotationMatrix(new THREE.Matrix4().makeBasis(x, y, z));
    lights.push(light);
    // Its shadows: a point light of no intensity at its centre (a hair in front, off the
    // ceiling it hangs from) casts the shadow map the area light's shading reads
    // (areaLightShadows): hard shadows from the centre, where Blender's are soft.
    if (proxies.length >= shadowed || !areaCastsShadow(a)) continue;
    const proxy = new THREE.PointLight(0xffffff, 0);
    proxy.position.fromArray(a.position).addScaledVector(z, -1e-3 * Math.max(a.size_x, a.size_y, 1e-3));
    castShadows(proxy, proxy, bounds);
    proxies.push(proxy);
  }
  // First in the scene: three.js numbers shadowed point lights in scene order, and the area
  // lights' shading reads point shadow i for area light i.
  return [...proxies, ...lights];
}

// How many of the scene's area lights cast shadows: the first few, since each costs a cube
// shadow map (six passes a frame) and a texture unit in every material's shader (WebGL2
// guarantees 16); the rest light the page unshadowed.
const MAX_SHADOWED_AREA_LIGHTS = 4;
function areaCastsShadow(area) {
  return area.cast_shadow !== false && Math.max(...area.radiance) > 0;
}

export function shadowedAreaLightCount(gltf) {
  const areas = gltf.extras?.bakegi?.area_lights ?? [];
  const lit = areas.filter(areaCastsShadow).length;
  return Math.min(lit, MAX_SHADOWED_AREA_LIGHTS);
}

// Area lights' direct light through their shadow proxies' maps (makeLights): three.js'
// lights_fragment_begin with the term of RectAreaLight i < count scaled by point shadow i
// (the proxies come first among the shadowed point lights).
const AREA_LIGHT_TERM =
  "RE_Direct_RectArea( rectAreaLight, geometryPosition, geometryNormal, geometryViewDir, geometryClearcoatNormal, material, reflectedLight );";
const SHADOWED_AREA_LIGHT_TERM = `{
    ReflectedLight bakegiArea = ReflectedLight( vec3( 0.0 ), vec3( 0.0 ), vec3( 0.0 ), vec3( 0.0 ) );
    RE_Direct_RectArea( rectAreaLight, geometryPosition, geometryNormal, geometryViewDir, geometryClearcoatNormal, material, bakegiArea );
    float bakegiShadow = 1.0;
    #if defined( USE_SHADOWMAP ) && ( UNROLLED_LOOP_INDEX < BAKEGI_SHADOWED_AREA_LIGHTS ) && ( UNROLLED_LOOP_INDEX < NUM_POINT_LIGHT_SHADOWS )
    bakegiShadow = receiveShadow ? getPointShadow( pointShadowMap[ i ], pointLightShadows[ i ].shadowMapSize, pointLightShadows[ i ].shadowIntensity, pointLightShadows[ i ].shadowBias, pointLightShadows[ i ].shadowRadius, vPointShadowCoord[ i ], pointLightShadows[ i ].shadowCameraNear, pointLightShadows[ i ].shadowCameraFar ) : 1.0;
    #endif
    reflectedLight.directDiffuse += bakegiShadow * bakegiArea.directDiffuse;
    reflectedLight.directSpecular += bakegiShadow * bakegiArea.directSpecular;
  }`;

export function areaLightShadows(material, count) {
  const chunk = THREE.ShaderChunk.lights_fragment_begin;
  if (!(count > 0) || !chunk.includes(AREA_LIGHT_TERM)) return; // unshadowed, as before
  const shadowed = `#define BAKEGI_SHADOWED_AREA_LIGHTS ${count}\n` +
    chunk.replace(AREA_LIGHT_TERM, SHADOWED_AREA_LIGHT_TERM);
  const previous = material.onBeforeCompile;
  const previousKey = material.customProgramCacheKey;
  material.onBeforeCompile = (shader, renderer) => {
    previous.call(material, shader, renderer);
    shader.fragmentShader = shader.fragmentShader.replace("#include <lights_fragment_begin>", shadowed);
  };
  material.customProgramCacheKey = () => previousKey.call(material) + `+bakegi-area-shadows-${count}`;
}

// Called when a texture has arrived (the page redraws).
let onTextureLoaded = () => {};
export function setTextureListener(listener) {
  onTextureLoaded = listener;
}

// Resolves when every texture asked for so far has arrived or failed: the page says it is
// done only then, with them drawn.
const pendingTextures = [];
export function texturesSettled() {
  return Promise.all(pendingTextures);
}

// The glTF camera (a PerspectiveCamera with its node's pose), or null.
export function makeCamera(gltf, aspect) {
  for (const node of gltf.nodes ?? []) {
    if (node.camera === undefined) continue;
    const p = gltf.cameras[node.camera].perspective;
    const camera = new THREE.PerspectiveCamera(THREE.MathUtils.radToDeg(p.yfov), aspect, p.znear ?? 0.01, p.zfar ?? 1000);
    nodeTransform(camera, node);
    return camera;
  }
  return null;
}

// The primitives in file order with what the stream and a local load need.
export function primitivesOf(gltf) {
  const out = [];
  (gltf.meshes ?? []).forEach((mesh, m) =>
    mesh.primitives.forEach((primitive, p) => out.push({ mesh: m, primitive: p, description: primitive })));
  return out;
}
