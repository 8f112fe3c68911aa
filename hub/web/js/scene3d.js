// A 3D view of the capture volume (three.js from Debian's libjs-three, r111): floor grid,
// cameras with view cones from the calibration, markers (confirmed and provisional, with ids on
// demand), rigid bodies with their axes, skeletons' bones (serve --skeleton) as lines from each
// joint centre to its parent's; orbit, pan and zoom with the mouse. Millimetres, the
// calibration's world frame, its up axis guessed from the cameras (they hang upright).
//
// It renders only while shown; `drawnMarkers` is the number of markers the last render drew,
// `drawnFramePoints` the points of the frame it showed, and `fps` the rendering rate over the
// last second (the web test and the benchmark read them).
import * as THREE from '/vendor/three/build/three.module.js';
import { OrbitControls } from '/vendor/three/examples/jsm/controls/OrbitControls.js';

const MARKER_RADIUS_MM = 14;  // drawn larger than real markers, to be seen across the volume
const CONE_DEPTH_MM = 700;

// The world axis closest to the cameras' mean "up" (-y of each camera, in world coordinates).
function upAxisOf(cameras) {
  const up = new THREE.Vector3();
  for (const c of cameras) up.add(new THREE.Vector3(-c.rotation[1][0], -c.rotation[1][1], -c.rotation[1][2]));
  if (up.lengthSq() === 0) return new THREE.Vector3(0, 0, 1);
  const a = [Math.abs(up.x), Math.abs(up.y), Math.abs(up.z)];
  const i = a.indexOf(Math.max(...a));
  const axis = new THREE.Vector3();
  axis.setComponent(i, Math.sign(up.getComponent(i)));
  return axis;
}

// Antialiasing multiplies a software renderer's work (SwiftShader or llvmpipe, where there is no
// GPU: 22 instead of 53 fps with 150 markers in headless Chromium); with a GPU it is free.
function softwareGl() {
  const gl = document.createElement('canvas').getContext('webgl');
  if (!gl) return true;
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const renderer = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : '';
  gl.getExtension('WEBGL_lose_context')?.loseContext();
  return /swiftshader|llvmpipe|software/i.test(renderer);
}
export const SOFTWARE_GL = softwareGl();

// A live point's label: its track's id, the same while provisional (drawn in another colour)
// and once confirmed; '?' for a point no track took.
export function markerLabel(id) {
  return id < 0 ? '?' : String(id);
}

export class Scene3D {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: !SOFTWARE_GL });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0x15181d);
    container.append(this.renderer.domElement);
    this.labels = document.createElement('canvas');
    this.labels.className = 'labels';
    container.append(this.labels);

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(45, 1, 10, 200000);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x334455, 1.1));

    this.up = new THREE.Vector3(0, 0, 1);
    this.grid = null;
    this.cameraGroup = new THREE.Group();
    this.scene.add(this.cameraGroup);
    this.cameraLabels = [];
    this.setUp(this.up);

    this.sphere = new THREE.SphereBufferGeometry(MARKER_RADIUS_MM, 12, 8);
    this.materials = {
      confirmed: new THREE.MeshLambertMaterial({ color: 0x4fd18b }),
      provisional: new THREE.MeshLambertMaterial({ color: 0xf0a33a }),
    };
    this.capacity = 0;
    this.meshes = {};
    this.ensureCapacity(256);
    this.points = [];
    this.bodies = [];
    this.bodyAxes = [];
    this.boneLines = new THREE.LineSegments(new THREE.BufferGeometry(),
                                            new THREE.LineBasicMaterial({ color: 0x7fb4ff }));
    this.boneLines.frustumCulled = false;
    this.scene.add(this.boneLines);
    this.drawnBones = 0;    // bones the last setSkeletons drew (the web test reads it)
    this.showIds = false;
    this.names = null;      // marker names by id (playback of a TRC)

    this.active = false;
    this.drawnMarkers = 0;
    this.framesRendered = 0;
    this.fps = 0;
    this.fpsWindow = { start: performance.now(), frames: 0 };
    this.matrix = new THREE.Matrix4();
    this.loop = () => this.renderFrame();
    new ResizeObserver(() => this.resize()).observe(container);
  }

  setUp(up) {
    this.up = up.clone();
    this.camera.up.copy(up);
    if (this.grid) this.scene.remove(this.grid);
    // 8 m × 8 m, lines every 0.5 m, in the plane through the origin normal to the up axis.
    this.grid = new THREE.GridHelper(8000, 16, 0x5b6470, 0x2c333c);
    this.grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), up);
    this.scene.add(this.grid);
    const axes = new THREE.AxesHelper(400);
    this.grid.add(axes);
    axes.quaternion.copy(this.grid.quaternion.clone().inverse());
  }

  // cameras: /api/calibration's list. Draws each as a view cone to CONE_DEPTH_MM and frames the
  // view on them.
  setCameras(cameras) {
    this.scene.remove(this.cameraGroup);
    this.cameraGroup = new THREE.Group();
    this.cameraLabels = [];
    const positions = [];
    const centre = new THREE.Vector3();
    for (const c of cameras) {
      const R = new THREE.Matrix3().set(...c.rotation[0], ...c.rotation[1], ...c.rotation[2]);
      const Rt = R.clone().transpose();
      const t = new THREE.Vector3(...c.translation);
      const toWorld = (v) => v.clone().sub(t).applyMatrix3(Rt);
      const eye = new THREE.Vector3(...c.centre);
      const corners = [[0, 0], [c.width, 0], [c.width, c.height], [0, c.height]].map(([u, v]) =>
        toWorld(new THREE.Vector3((u - c.cx) / c.fx, (v - c.cy) / c.fy, 1).multiplyScalar(CONE_DEPTH_MM)));
      for (let i = 0; i < 4; ++i) positions.push(eye, corners[i], corners[i], corners[(i + 1) % 4]);
      centre.add(eye);
      this.cameraLabels.push({ id: c.id, position: eye });
    }
    const geometry = new THREE.BufferGeometry().setFromPoints(positions);
    this.cameraGroup.add(new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0x6aa6ff })));
    this.scene.add(this.cameraGroup);
    if (cameras.length) {
      this.setUp(upAxisOf(cameras));
      centre.divideScalar(cameras.length);
      // Look at the middle of the volume below the cameras, from above and outside the ring.
      const height = centre.dot(this.up);
      const floor = centre.clone().sub(this.up.clone().multiplyScalar(height));
      const target = floor.clone().add(this.up.clone().multiplyScalar(height * 0.4));
      let radius = 0;
      for (const c of cameras) radius = Math.max(radius, new THREE.Vector3(...c.centre).distanceTo(floor));
      const diagonal = new THREE.Vector3(1, 1, 1);
      const side = diagonal.sub(this.up.clone().multiplyScalar(this.up.dot(diagonal)));
      this.camera.position.copy(target).add(side.normalize().multiplyScalar(radius * 1.3))
        .add(this.up.clone().multiplyScalar(radius * 0.6));
      this.controls.target.copy(target);
      this.controls.update();
    }
  }

  ensureCapacity(n) {
    if (n <= this.capacity) return;
    this.capacity = Math.max(n, this.capacity * 2);
    for (const kind of ['confirmed', 'provisional']) {
      if (this.meshes[kind]) this.scene.remove(this.meshes[kind]);
      const mesh = new THREE.InstancedMesh(this.sphere, this.materials[kind], this.capacity);
      mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
      mesh.count = 0;
      mesh.frustumCulled = false;
      this.meshes[kind] = mesh;
      this.scene.add(mesh);
    }
  }

  // points: [[x, y, z, id, provisional, ...], ...] as /api/live sends them.
  setPoints(points) {
    this.points = points;
    this.ensureCapacity(points.length);
    let confirmed = 0, provisional = 0;
    const { confirmed: c, provisional: p } = this.meshes;
    for (const point of points) {
      this.matrix.makeTranslation(point[0], point[1], point[2]);
      if (point[4]) p.setMatrixAt(provisional++, this.matrix);
      else c.setMatrixAt(confirmed++, this.matrix);
    }
    c.count = confirmed;
    p.count = provisional;
    c.instanceMatrix.needsUpdate = true;
    p.instanceMatrix.needsUpdate = true;
  }

  // A bound mesh (mesh_binding.js) drawn with flat shading from its triangles; null removes it.
  setMesh(binding) {
    if (this.mesh) {
      this.scene.remove(this.mesh);
      this.mesh.geometry.dispose();
      this.mesh = null;
    }
    if (!binding) return;
    const geometry = new THREE.BufferGeometry();
    const position = new THREE.BufferAttribute(Float32Array.from(binding.bound), 3);
    position.setUsage(THREE.DynamicDrawUsage);
    geometry.setAttribute('position', position);
    geometry.setIndex(new THREE.BufferAttribute(binding.index, 1));
    this.mesh = new THREE.Mesh(geometry, new THREE.MeshNormalMaterial({ flatShading: true, side: THREE.DoubleSide }));
    this.mesh.frustumCulled = false;
    this.scene.add(this.mesh);
  }

  // The mesh's vertices for the next render (Float32Array, 3 per vertex).
  updateMesh(positions) {
    const attribute = this.mesh.geometry.attributes.position;
    attribute.array.set(positions);
    attribute.needsUpdate = true;
  }

  // bodies: [[id, tracked, predicted, x, y, z, qx, qy, qz, qw, error, markers], ...].
  setBodies(bodies) {
    this.bodies = bodies;
    while (this.bodyAxes.length < bodies.length) {
      const axes = new THREE.AxesHelper(250);
      axes.material.linewidth = 2;
      this.bodyAxes.push(axes);
      this.scene.add(axes);
    }
    this.bodyAxes.forEach((axes, i) => {
      const b = bodies[i];
      axes.visible = Boolean(b && (b[1] || b[2]));
      if (!axes.visible) return;
      axes.position.set(b[3], b[4], b[5]);
      axes.quaternion.set(b[6], b[7], b[8], b[9]);
    });
  }

  // skeletons: /api/live's [{name, solved, bones: [[name, parent, x, y, z, qx, qy, qz, qw], ...]}];
  // a skeleton not solved in this frame has no bones and draws nothing.
  setSkeletons(skeletons) {
    const positions = [];
    for (const s of skeletons) {
      for (const b of s.solved ? s.bones : []) {
        if (b[1] < 0 || !s.bones[b[1]]) continue;
        const p = s.bones[b[1]];
        positions.push(p[2], p[3], p[4], b[2], b[3], b[4]);
      }
    }
    this.boneLines.geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
    this.drawnBones = positions.length / 6;
  }

  show() {
    if (this.active) return;
    this.active = true;
    this.resize();
    requestAnimationFrame(this.loop);
  }

  hide() { this.active = false; }

  resize() {
    const w = this.container.clientWidth, h = this.container.clientHeight;
    if (!w || !h) return;
    this.renderer.setSize(w, h);
    this.labels.width = w;
    this.labels.height = h;
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  renderFrame() {
    if (!this.active) return;
    if (this.beforeRender) this.beforeRender();
    this.renderer.render(this.scene, this.camera);
    this.drawnMarkers = this.meshes.confirmed.count + this.meshes.provisional.count;
    this.drawnFramePoints = this.points.length;  // the points of the frame this render showed
    this.drawLabels();
    this.framesRendered += 1;
    const now = performance.now();
    this.fpsWindow.frames += 1;
    if (now - this.fpsWindow.start >= 1000) {
      this.fps = (this.fpsWindow.frames * 1000) / (now - this.fpsWindow.start);
      this.fpsWindow = { start: now, frames: 0 };
    }
    requestAnimationFrame(this.loop);
  }

  drawLabels() {
    const ctx = this.labels.getContext('2d');
    ctx.clearRect(0, 0, this.labels.width, this.labels.height);
    ctx.font = '11px sans-serif';
    const v = new THREE.Vector3();
    const put = (position, text, colour) => {
      v.copy(position).project(this.camera);
      if (v.z > 1) return;
      ctx.fillStyle = colour;
      ctx.fillText(text, (v.x + 1) * 0.5 * this.labels.width + 6, (1 - v.y) * 0.5 * this.labels.height - 6);
    };
    for (const c of this.cameraLabels) put(c.position, `cam ${c.id}`, '#8fb8ff');
    if (!this.showIds) return;
    for (const p of this.points) {
      const id = p[3];
      // A live point's name (serve --labels: its eighth element) wins; playback names by column.
      const text = p[7] || (this.names ? this.names[id] || '?' : markerLabel(id));
      put(v.set(p[0], p[1], p[2]).clone(), text, p[4] ? '#f0c07a' : '#bdf0d2');
    }
  }
}
