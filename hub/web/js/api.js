// The hub's HTTP API as the console uses it: JSON in and out, errors as ApiError with the hub's
// reason, and a count of the bytes each client receives (the console's traffic figure). The hub
// wants a login (its session cookie, HttpOnly: this code never sees it): any 401 calls the
// handler main.js sets, which shows the login form. State changes go as JSON with the
// X-Mocap-Request header, which a page elsewhere cannot send without the hub's consent.
export const traffic = { httpBytes: 0, wsBytes: 0, requests: 0 };

let unauthorized = () => {};
export function onUnauthorized(handler) { unauthorized = handler; }
// Logins so far: a 401 to a request sent before the latest login is stale (the cookie was not
// set yet when it left) and must not bring the form back.
let logins = 0;
function refused(sentAfterLogins) { if (sentAfterLogins === logins) unauthorized(); }

export class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

async function answer(response, sentAfterLogins) {
  const text = await response.text();
  traffic.httpBytes += text.length;
  traffic.requests += 1;
  let body = null;
  try {
    body = text ? JSON.parse(text) : null;
  } catch (e) {
    throw new ApiError(response.status, `not JSON: ${text.slice(0, 80)}`);
  }
  if (response.status === 401) refused(sentAfterLogins);
  if (!response.ok) throw new ApiError(response.status, (body && body.error) || response.statusText);
  return body;
}

async function send(method, path, body) {
  const sentAfterLogins = logins;
  let response;
  try {
    response = await fetch(path, {
      method,
      cache: 'no-store',
      headers: method === 'GET' ? {} : { 'Content-Type': 'application/json', 'X-Mocap-Request': '1' },
      body: body === undefined ? undefined : JSON.stringify(body),
    });
  } catch (e) {
    throw new ApiError(0, 'the hub does not answer');
  }
  return answer(response, sentAfterLogins);
}

export const getJson = (path) => send('GET', path);
export const postJson = (path, body) => send('POST', path, body === undefined ? {} : body);
export const deleteJson = (path) => send('DELETE', path);
export const putJson = (path, body) => send('PUT', path, body);
export async function login(token) {
  const who = await send('POST', '/api/login', { token });
  logins += 1;
  return who;
}
export const logout = () => send('POST', '/api/logout', {});

// A file's text (session files for playback).
export async function getText(path) {
  const sentAfterLogins = logins;
  const response = await fetch(path, { cache: 'no-store' });
  const text = await response.text();
  traffic.httpBytes += text.length;
  traffic.requests += 1;
  if (response.status === 401) refused(sentAfterLogins);
  if (!response.ok) {
    let reason = response.statusText;
    try { reason = JSON.parse(text).error || reason; } catch (e) { /* not JSON: keep the status text */ }
    throw new ApiError(response.status, reason);
  }
  return text;
}

// A binary file (a mesh binding) as an ArrayBuffer.
export async function getBytes(path) {
  const sentAfterLogins = logins;
  const response = await fetch(path, { cache: 'no-store' });
  const bytes = await response.arrayBuffer();
  traffic.httpBytes += bytes.byteLength;
  traffic.requests += 1;
  if (response.status === 401) refused(sentAfterLogins);
  if (!response.ok) throw new ApiError(response.status, response.statusText);
  return bytes;
}

// A PNG (node previews) as an image bitmap.
export async function getImage(path) {
  const sentAfterLogins = logins;
  const response = await fetch(path, { cache: 'no-store' });
  const blob = await response.blob();
  traffic.httpBytes += blob.size;
  traffic.requests += 1;
  if (response.status === 401) refused(sentAfterLogins);
  if (!response.ok) {
    let reason = response.statusText;
    try { reason = JSON.parse(await blob.text()).error || reason; } catch (e) { /* keep the status */ }
    throw new ApiError(response.status, reason);
  }
  return createImageBitmap(blob);
}

// Small DOM helper: el('td', {class: 'x', text: 'y'}, child, ...).
export function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (key === 'text') node.textContent = value;
    else if (key.startsWith('on')) node.addEventListener(key.slice(2), value);
    else node.setAttribute(key, value);
  }
  for (const child of children) node.append(child);
  return node;
}

export function formatNumber(value, digits = 1) {
  return value === null || value === undefined || Number.isNaN(value) ? '–' : Number(value).toFixed(digits);
}
