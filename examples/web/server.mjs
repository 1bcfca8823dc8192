// A tiny static file server for the viewer (no dependencies): examples/web/ at /, and folders
// mounted under prefixes, e.g. the repository's data/ or a test's output folder.
//   node server.mjs [--port N] [--mount /prefix=DIR ...]      (port 0: any free port; prints the URL)
// Only GET and HEAD; paths are confined to their folder.
import { createServer } from 'node:http';
import { readFile, stat } from 'node:fs/promises';
import { extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const k_types = {
    '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript',
    '.json': 'application/json', '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json',
    '.bin': 'application/octet-stream', '.png': 'image/png', '.jpg': 'image/jpeg',
    '.ply': 'application/octet-stream', '.obj': 'text/plain', '.mtl': 'text/plain',
    '.vert': 'text/plain', '.frag': 'text/plain', '.glsl': 'text/plain',
    '.ktx2': 'image/ktx2', '.wasm': 'application/wasm',
};

// mounts: [[prefix, dir]], longest prefix first
export function serve(mounts, port = 0, host = '127.0.0.1') {
    const roots = mounts.map(([prefix, dir]) => [prefix.replace(/\/+$/, '') + '/', resolve(dir)])
        .sort((a, b) => b[0].length - a[0].length);
    const server = createServer(async (request, response) => {
        try {
            if (request.method !== 'GET' && request.method !== 'HEAD') throw Object.assign(new Error('method'), { code: 405 });
            const path = decodeURIComponent(new URL(request.url, 'http://x').pathname);
            const root = roots.find(([prefix]) => path.startsWith(prefix) || path + '/' === prefix);
            if (!root) throw Object.assign(new Error('not found'), { code: 404 });
            let file = normalize(join(root[1], path.slice(root[0].length)));
            if (file !== root[1] && !file.startsWith(root[1] + sep)) throw Object.assign(new Error('outside'), { code: 403 });
            if ((await stat(file)).isDirectory()) file = join(file, 'index.html');
            const body = await readFile(file);
            response.writeHead(200, { 'content-type': k_types[extname(file).toLowerCase()] || 'application/octet-stream',
                'cache-control': 'no-store' });
            response.end(request.method === 'HEAD' ? undefined : body);
        } catch (error) {
            const code = error.code === 'ENOENT' || error.code === 'ENOTDIR' ? 404 : typeof error.code === 'number' ? error.code : 500;
            response.writeHead(code, { 'content-type': 'text/plain' });
            response.end(`${code}\n`);
        }
    });
    return new Promise((resolve_listen) => server.listen(port, host, () => resolve_listen(server)));
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
    const here = fileURLToPath(new URL('.', import.meta.url));
    const mounts = [['/', here], ['/data', join(here, '..', '..', 'data')]];
    let port = 8080;
    const args = process.argv.slice(2);
    for (let i = 0; i < args.length; ++i) {
        if (args[i] === '--port') port = Number(args[++i]);
        else if (args[i] === '--mount') {
            const m = /^([^=]+)=(.+)$/.exec(args[++i] || '');
            if (!m) { console.error('server: --mount /prefix=DIR'); process.exit(2); }
            mounts.push([m[1], m[2]]);
        } else { console.error(`server: unknown argument ${args[i]}`); process.exit(2); }
    }
    const server = await serve(mounts, port);
    console.log(`http://127.0.0.1:${server.address().port}/`);
}
