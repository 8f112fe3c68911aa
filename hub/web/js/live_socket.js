// The /api/live WebSocket with reconnection: while started it stays connected, trying again
// every 0.5-2 s after the hub goes away (a serve restart), and hands each frame to its listeners.
import { traffic } from './api.js';

export class LiveSocket {
  constructor(path) {
    this.path = path;
    this.listeners = new Set();
    this.stateListeners = new Set();
    this.state = 'stopped';
    this.framesReceived = 0;
    this.connections = 0;
    this.retryMs = 500;
    this.ws = null;
    this.timer = null;
  }

  start() {
    if (this.state !== 'stopped') return;
    this.setState('connecting');
    this.connect();
  }

  stop() {
    clearTimeout(this.timer);
    this.setState('stopped');
    if (this.ws) this.ws.close();
    this.ws = null;
  }

  connect() {
    const scheme = location.protocol === 'https:' ? 'wss://' : 'ws://';
    const ws = new WebSocket(scheme + location.host + this.path);
    this.ws = ws;
    ws.onopen = () => {
      this.retryMs = 500;
      this.connections += 1;
      this.setState('open');
    };
    ws.onmessage = (event) => {
      traffic.wsBytes += event.data.length;
      this.framesReceived += 1;
      const frame = JSON.parse(event.data);
      for (const listener of this.listeners) listener(frame);
    };
    ws.onerror = () => ws.close();
    ws.onclose = () => {
      if (this.ws !== ws || this.state === 'stopped') return;
      this.setState('reconnecting');
      this.timer = setTimeout(() => this.connect(), this.retryMs);
      this.retryMs = Math.min(this.retryMs * 2, 2000);
    };
  }

  setState(state) {
    this.state = state;
    for (const listener of this.stateListeners) listener(state);
  }
}
