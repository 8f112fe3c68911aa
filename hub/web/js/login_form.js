// The login form: shown over the console whenever the hub answers 401 (no login yet, or it
// expired), it sends the token typed in to POST /api/login; the hub answers with its session
// cookie (HttpOnly, SameSite=Strict) and the form goes away. The token is not kept by the page.
import { ApiError, el, login } from './api.js';

export class LoginForm {
  constructor(onLoggedIn) {
    this.onLoggedIn = onLoggedIn;
    this.input = el('input', { id: 'login-token', type: 'password', autocomplete: 'current-password',
                               placeholder: 'API token (64 hex digits)', size: '70' });
    this.error = el('p', { id: 'login-error', class: 'error' });
    this.form = el('form', { id: 'login-form', class: 'login' },
      el('h2', { text: 'Log in to the hub' }),
      el('p', { text: 'Paste a token issued by `mocap-hub tokens new` (the local operator\'s is in '
                      + 'api-auth/operator.token beside serve\'s sessions).' }),
      this.input, el('button', { id: 'login-submit', type: 'submit', text: 'Log in' }), this.error);
    this.form.addEventListener('submit', (event) => {
      event.preventDefault();
      this.submit();
    });
    this.overlay = el('div', { id: 'login', class: 'login-overlay', hidden: '' }, this.form);
    document.body.append(this.overlay);
  }

  get shown() { return !this.overlay.hidden; }

  show() {
    if (this.shown) return;
    this.overlay.hidden = false;
    this.input.focus();
  }

  async submit() {
    this.error.textContent = '';
    try {
      const who = await login(this.input.value.trim());
      this.input.value = '';
      this.overlay.hidden = true;
      this.onLoggedIn(who);
    } catch (e) {
      this.error.textContent = e instanceof ApiError && e.status === 401 ? 'That token is not valid.' : e.message;
    }
  }
}
