// api.js - the page's client of the public texoptd API (openapi.yaml). Everything goes
// through fetch so that the token, when one is given, travels in the Authorization header:
// never in a URL, where it would reach logs and history. The event stream is read with
// fetch too (EventSource cannot send headers), and results are downloaded into a Blob.

let token = sessionStorage.getItem('texopt-token') || '';

export function setToken(value) {
  token = value;
  if (value) sessionStorage.setItem('texopt-token', value);
  else sessionStorage.removeItem('texopt-token');
}

export function getToken() { return token; }

export async function call(path, options = {}) {
  const headers = new Headers(options.headers || {});
  if (token) headers.set('Authorization', 'Bearer ' + token);
  const response = await fetch(path, { ...options, headers });
  if (!response.ok && response.status !== 304) {
    let detail = response.statusText;
    try {
      const problem = await response.json();
      detail = problem.detail || problem.title || detail;
    } catch { /* not problem+json */ }
    const error = new Error(`${response.status}: ${detail}`);
    error.status = response.status;
    throw error;
  }
  return response;
}

export async function json(path, options) {
  return (await call(path, options)).json();
}

// The Params schema of openapi.yaml: {name: {type, enum, minimum, maximum, exclusiveMinimum,
// exclusiveMaximum, default, description}}. Reads only the regular subset the file is
// written in (two-space indentation, `key: value`, flow lists), and follows a $ref to a
// schema of components.schemas.
export function paramsSchema(yaml) {
  const lines = yaml.split('\n');
  const schemaAt = name => lines.indexOf(`    ${name}:`);
  const block = (start, indent) => {
    const out = [];
    for (let i = start + 1; i < lines.length; i++) {
      const line = lines[i];
      if (line.trim() === '') continue;
      if (line.length - line.trimStart().length < indent) break;
      out.push(line);
    }
    return out;
  };
  const fields = (blockLines, indent) => {
    const out = {};
    for (const line of blockLines) {
      const m = line.match(/^( *)([A-Za-z$]\w*): ?(.*)$/);
      if (!m || m[1].length !== indent) continue;
      out[m[2]] = scalar(m[3]);
    }
    return out;
  };
  const start = schemaAt('Params');
  if (start < 0) throw new Error('openapi.yaml has no Params schema');
  const body = block(start, 6);
  const propsAt = body.indexOf('      properties:');
  const result = {};
  let name = null, own = [];
  const flush = () => {
    if (!name) return;
    let f = fields(own, 10);
    if (f.$ref) f = { ...fields(block(schemaAt(f.$ref.split('/').pop()), 6), 6), ...f };
    result[name] = f;
  };
  for (const line of body.slice(propsAt + 1)) {
    const m = line.match(/^ {8}(\w+):\s*$/);
    if (m) { flush(); name = m[1]; own = []; } else own.push(line);
  }
  flush();
  return result;
}

function scalar(text) {
  const t = text.trim();
  if (t.startsWith('[') && t.endsWith(']'))
    return t.slice(1, -1).split(',').map(s => scalar(s)).filter(s => s !== '');
  if (/^'.*'$/.test(t) || /^".*"$/.test(t)) return t.slice(1, -1);
  if (t === 'true' || t === 'false') return t === 'true';
  if (t !== '' && !isNaN(Number(t))) return Number(t);
  return t;
}

// Reads a job's server-sent events with fetch; calls onEvent(name, job) for each. Resumes
// after a dropped connection with Last-Event-ID; resolves when the job has ended (204, or
// the stream closes on a finished job). signal stops it.
export async function followEvents(id, onEvent, signal) {
  let lastId = null;
  for (;;) {
    const headers = lastId ? { 'Last-Event-ID': lastId } : {};
    let response;
    try {
      response = await call(`/v1/jobs/${id}/events`, { headers, signal });
    } catch (error) {
      if (signal && signal.aborted) return;
      throw error;
    }
    if (response.status === 204) return;
    const reader = response.body.pipeThrough(new TextDecoderStream()).getReader();
    let buffer = '', finished = false;
    for (;;) {
      let chunk;
      try {
        chunk = await reader.read();
      } catch (error) {
        if (signal && signal.aborted) return;
        break; // the connection dropped: resume below
      }
      if (chunk.done) break;
      buffer += chunk.value;
      let end;
      while ((end = buffer.indexOf('\n\n')) >= 0) {
        const record = buffer.slice(0, end);
        buffer = buffer.slice(end + 2);
        let name = 'message', data = '';
        for (const line of record.split('\n')) {
          if (line.startsWith('id:')) lastId = line.slice(3).trim();
          else if (line.startsWith('event:')) name = line.slice(6).trim();
          else if (line.startsWith('data:')) data += line.slice(5).trim();
        }
        const job = data ? JSON.parse(data) : {};
        onEvent(name, job);
        if (name === 'deleted' || ['succeeded', 'failed', 'canceled'].includes(job.state)) finished = true;
      }
    }
    if (finished || (signal && signal.aborted)) return;
    await new Promise(resolve => setTimeout(resolve, 1000));
  }
}
