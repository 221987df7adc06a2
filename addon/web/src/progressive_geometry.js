// One primitive's progressive mesh on the page (§4.2): vertices arrive coarse first; each
// received face is drawn with every corner not yet received replaced by the vertex it
// collapses onto (the lookup table, recursively), so the mesh refines as vertices arrive.
import * as THREE from "three";

export class ProgressiveGeometry {
  constructor(vertexCount, faceCount, hasNormals, hasUvs) {
    this.vertexCount = vertexCount;
    this.faceCount = faceCount;
    this.received = 0;
    this.faces = new Uint32Array(3 * faceCount);
    this.facesReceived = 0;
    this.parent = new Uint32Array(vertexCount);
    this.geometry = new THREE.BufferGeometry();
    this.positions = new THREE.BufferAttribute(new Float32Array(3 * vertexCount), 3);
    this.geometry.setAttribute("position", this.positions);
    if (hasNormals) {
      this.normals = new THREE.BufferAttribute(new Float32Array(3 * vertexCount), 3);
      this.geometry.setAttribute("normal", this.normals);
    }
    if (hasUvs) {
      this.uvs = new THREE.BufferAttribute(new Float32Array(2 * vertexCount), 2);
      this.geometry.setAttribute("uv", this.uvs);
    }
    // Whether each vertex reads the grid at all (the export's _BAKEGI_READS_GRID); 1 until told
    // otherwise, and for scenes exported without it.
    this.readsGrid = new THREE.BufferAttribute(new Float32Array(vertexCount).fill(1), 1);
    this.geometry.setAttribute("bakegiReadsGrid", this.readsGrid);
  }

  add(entry) {
    if (entry.first !== this.received) throw new Error("geometry arrived out of order");
    this.positions.array.set(entry.positions, 3 * entry.first);
    if (this.normals && entry.normals) this.normals.array.set(entry.normals, 3 * entry.first);
    if (this.uvs && entry.uvs) this.uvs.array.set(entry.uvs, 2 * entry.first);
    if (entry.readsGrid) this.readsGrid.array.set(entry.readsGrid, entry.first);
    this.received += entry.vertexCount;
    this.faces.set(entry.faces, 3 * this.facesReceived);
    this.facesReceived += entry.faces.length / 3;
    for (let i = 0; i < entry.lookups.length; i += 2) this.parent[entry.lookups[i]] = entry.lookups[i + 1];
  }

  // Everything at once (a whole glTF from a local folder).
  setAll(positions, normals, uvs, readsGrid, faces, parent) {
    this.positions.array.set(positions);
    if (this.normals && normals) this.normals.array.set(normals);
    if (this.uvs && uvs) this.uvs.array.set(uvs);
    if (readsGrid) this.readsGrid.array.set(readsGrid);
    this.faces.set(faces);
    this.parent.set(parent);
    this.received = this.vertexCount;
    this.facesReceived = this.faceCount;
  }

  fraction() {
    return this.vertexCount ? this.received / this.vertexCount : 1;
  }

  // The index buffer for what has arrived.
  update() {
    const n = this.received;
    const index = new Uint32Array(3 * this.facesReceived);
    for (let i = 0; i < index.length; ++i) {
      let v = this.faces[i];
      while (v >= n) v = this.parent[v];
      index[i] = v;
    }
    this.geometry.setIndex(new THREE.BufferAttribute(index, 1));
    this.positions.needsUpdate = true;
    if (this.normals) this.normals.needsUpdate = true;
    if (this.uvs) this.uvs.needsUpdate = true;
    this.readsGrid.needsUpdate = true;
    this.geometry.computeBoundingSphere();
  }
}
