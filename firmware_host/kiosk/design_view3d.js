// popcut designer's 3D view: the pattern's faces folded to any angle (eq. 7) and lit with cast shadows, in three.js.
'use strict';

// Pattern (x, v) on a face's plane to the card at 90°: a VFace at depth t stands at y = t
// (z = v + t), an HFace at height t lies at z = t (y = t - v). popcut's y runs from the back
// board to the front, z up; three.js has y up and z towards the viewer.
function cardPoint(kind, t, x, v) {
  return kind === 'V' ? [x, t, v + t] : [x, t - v, t];
}

// The parallel fold: every VFace stays parallel to the back board, every HFace to the floor, the
// back board turned to `deg` from the floor (0 flat, 90 standing, 180 closed).
function foldPoint(p, deg) {
  const a = deg * Math.PI / 180;
  const c = deg === 90 ? 0 : Math.cos(a), s = deg === 90 ? 1 : Math.sin(a);
  return [p[0], p[1] - p[2] * c, p[2] * s];
}

class CardView {
  constructor(container) {
    this.container = container;
    this.angle = 60;
    this.ok = typeof THREE !== 'undefined' && this.makeRenderer();
    if (!this.ok) {
      const note = document.createElement('div');
      note.className = 'no-webgl';
      note.textContent = typeof THREE === 'undefined'
        ? 'The 3D view needs three.js, which this server does not have (install libjs-three).'
        : 'This browser cannot show 3D (no WebGL); the pattern and check still follow every edit.';
      container.appendChild(note);
    }
  }

  makeRenderer() {
    let renderer;
    try {
      renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    } catch (_) {
      return false;
    }
    this.renderer = renderer;
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.shadowMap.enabled = true;
    renderer.shadowMap.type = THREE.PCFSoftShadowMap;
    this.container.appendChild(renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xeef2f5);
    this.camera = new THREE.PerspectiveCamera(35, 1, 1, 5000);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8170, 0.55));
    // One low sun from the front left: walls at different depths cast shadows on what lies behind.
    this.sun = new THREE.DirectionalLight(0xffffff, 0.75);
    this.sun.castShadow = true;
    this.sun.shadow.mapSize.set(2048, 2048);
    this.sun.shadow.bias = -0.002;
    this.scene.add(this.sun, this.sun.target);
    this.material = new THREE.MeshStandardMaterial({ vertexColors: THREE.VertexColors, side: THREE.DoubleSide,
      roughness: 0.9, metalness: 0 });
    this.mesh = new THREE.Mesh(new THREE.BufferGeometry(), this.material);
    this.mesh.castShadow = true;
    this.mesh.receiveShadow = true;
    this.scene.add(this.mesh);
    this.controls = new THREE.OrbitControls(this.camera, renderer.domElement);
    this.controls.addEventListener('change', () => this.draw());
    new ResizeObserver(() => this.resize()).observe(this.container);
    this.resize();
    return true;
  }

  resize() {
    const w = this.container.clientWidth, h = this.container.clientHeight;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.renderer.domElement.style.width = '100%';
    this.renderer.domElement.style.height = '100%';
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.draw();
  }

  // Faces of the pattern, coloured by kind, red where they would not stand, amber for flaps.
  setPattern(pattern, failing, flaps, dropped) {
    if (!this.ok) return;
    const card = [], colors = [];
    const bad = new THREE.Color(0xe0483c), flap = new THREE.Color(0xf0a030);
    const floor = -pattern.sheet.min[1], back = pattern.sheet.max[1];
    // Paper a little greyer the further back (walls) or lower (roofs) it lies, so faces at
    // different depths read apart even where no shadow falls between them.
    const shade = (f) => {
      const near = f.kind === 'V' ? f.t / Math.max(floor, 1) : f.t / Math.max(back, 1);
      const base = new THREE.Color(f.kind === 'V' ? 0xd8d2c4 : 0xddd3bd);
      return base.lerp(new THREE.Color(f.kind === 'V' ? 0xfffcf4 : 0xf1e8d2), Math.min(1, near * 1.6));
    };
    pattern.faces.forEach((f, i) => {
      if (dropped.has(i)) return;  // an opening's paper that falls out: not part of the card
      const color = failing.has(i) ? bad : flaps.has(i) ? flap : shade(f);
      const outer = f.outer.map(([x, v]) => new THREE.Vector2(x, v));
      const holes = f.holes.map((h) => h.map(([x, v]) => new THREE.Vector2(x, v)));
      const points = outer.concat(...holes);
      for (const tri of THREE.ShapeUtils.triangulateShape(outer, holes)) {
        for (const k of tri) {
          card.push(cardPoint(f.kind, f.t, points[k].x, points[k].y));
          colors.push(color.r, color.g, color.b);
        }
      }
    });
    this.card = card;
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(new Float32Array(card.length * 3), 3));
    g.setAttribute('color', new THREE.Float32BufferAttribute(colors, 3));
    this.mesh.geometry.dispose();
    this.mesh.geometry = g;
    const s = pattern.sheet;
    const first = !this.size;
    this.size = { width: s.max[0] - s.min[0], back: s.max[1], floor: -s.min[1] };
    if (first) this.frame();
    this.setAngle(this.angle);
  }

  // The camera in front, above and to the right of the card's middle, far enough for the whole sheet.
  frame() {
    const { width, back, floor } = this.size;
    const r = Math.max(width, back, floor);
    const centre = new THREE.Vector3(width / 2, back * 0.35, floor * 0.35);
    this.camera.position.set(width / 2 + r * 0.9, r * 1.1, r * 2.0);
    this.controls.target.copy(centre);
    this.sun.position.set(-r, r * 2, r * 1.5);
    this.sun.target.position.copy(centre);
    const cam = this.sun.shadow.camera;
    cam.left = cam.bottom = -r * 1.5;
    cam.right = cam.top = r * 1.5;
    cam.near = 1;
    cam.far = r * 6;
    cam.updateProjectionMatrix();
    this.controls.update();
  }

  setAngle(deg) {
    this.angle = deg;
    if (!this.ok || !this.card) return;
    const pos = this.mesh.geometry.getAttribute('position');
    this.card.forEach((p, i) => {
      const q = foldPoint(p, deg);
      pos.setXYZ(i, q[0], q[2], q[1]);
    });
    pos.needsUpdate = true;
    this.mesh.geometry.computeVertexNormals();
    this.mesh.geometry.computeBoundingSphere();
    this.draw();
  }

  draw() {
    if (this.ok) this.renderer.render(this.scene, this.camera);
  }
}

window.CardView = CardView;
