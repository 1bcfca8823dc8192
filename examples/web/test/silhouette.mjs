// The web viewer in a real headless browser (Chromium through playwright-core, WebGL2 on its
// SwiftShader), compared with `standin render` of the same thing from the same camera: the
// silhouette IoU (intersection over union of the pixels each covers, alpha >= 0.5) must reach
// --min-iou (0.95).
//   - harness cases: the original model drawn by the viewer against standin's ground-truth render
//     (checks the camera model, the loaders and the read-back);
//   - stand-in cases: a package baked by `standin bake`, exported by `standin export` to .glb, drawn
//     by the viewer, against `standin render` of the package (its own renderer).
//   - a KTX2 case: the grid atlas export rewritten by tools/ktx2.mjs (colour atlas as KTX2 / Basis
//     ETC1S, KHR_texture_basisu), drawn through three's KTX2Loader, against the same render
//     (from the first camera only: the encoding is what it checks, not the camera).
// Exit status: 0 pass, 1 fail, 77 skipped (no Chromium, or no npm to install playwright-core/three),
// 2 bad arguments. Registered in ctest as web_viewer_silhouette (tests/CMakeLists.txt).
//   node test/silhouette.mjs --cli build/standin [--work DIR] [--chromium /usr/bin/chromium]
//        [--min-iou 0.95] [--only NAME]
import { spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const web_dir = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const repo_dir = resolve(web_dir, '..', '..');
const k_skip = 77;

const options = { cli: null, work: null, chromium: process.env.STANDIN_CHROMIUM || '/usr/bin/chromium', min_iou: 0.95, only: null };
{
    const args = process.argv.slice(2);
    for (let i = 0; i < args.length; ++i) {
        const value = args[i + 1];
        if (args[i] === '--cli') options.cli = value;
        else if (args[i] === '--work') options.work = value;
        else if (args[i] === '--chromium') options.chromium = value;
        else if (args[i] === '--min-iou') options.min_iou = Number(value);
        else if (args[i] === '--only') options.only = value;
        else {
            console.error(`silhouette: unknown argument ${args[i]}`);
            process.exit(2);
        }
        ++i;
    }
    if (!options.cli) options.cli = join(repo_dir, 'build', 'standin');
    if (!options.work) options.work = join(repo_dir, 'build', 'web_viewer_test');
    if (!(options.min_iou > 0 && options.min_iou <= 1)) {
        console.error('silhouette: --min-iou must be in (0, 1]');
        process.exit(2);
    }
}

// The cameras, as `standin render` takes them (and the viewer's URL parameters): the protocol's
// three-quarter view for every case, and a view from behind and above for the stand-ins.
const k_size = '480x360';
const k_cameras = [
    { azimuth: 30, elevation: 20, distance: 1, fov: 40 },
    { azimuth: 200, elevation: 55, distance: 1, fov: 40, standins_only: true },
];

// What the cases bake and export is test data: the representations' names and options appear
// here as they do in tests/*_test.cpp. The grid atlas needs an octahedral view atlas.
const k_cases = [
    { name: 'model bunny.ply', model: 'data/bunny.ply' },
    { name: 'model box_textured.glb', model: 'data/box_textured.glb' },
    { name: 'view-atlas grid atlas', model: 'data/bunny.ply',
      bake: ['-r', 'view-atlas', '--layout', 'octahedral', '--frames', '16', '--resolution', '192'],
      export: ['--atlas-size', '2048'], proxy: 'hull', ktx2: ['--etc1s'] }, // drawn on the atlas hull (issue #16), not the quad
    // alpha-masked leaf cards (issue #16): thin leaves through the web grid shader's walk
    { name: 'view-atlas grid atlas tree', generate: ['tree', '-t', '4000', '--seed', '1'], model: 'tree.gltf',
      bake: ['-r', 'view-atlas', '--layout', 'octahedral', '--frames', '16', '--resolution', '192'], export: [], proxy: 'hull' },
    { name: 'displaced-mesh', model: 'data/bunny.ply', bake: ['-r', 'displaced-mesh'], export: [] },
    // alpha-masked leaf cards (issue #14): the export must keep the cut-outs the renderer discards.
    // First camera only (0.984; the second, 0.979, took 14-19 s of CI for the same export path: the
    // 101 MiB glb of the cards refined at tau 1 px, which SwiftShader draws slowly; `--pixels 480`
    // halves that but loses leaf detail, 0.969)
    { name: 'displaced-mesh tree', generate: ['tree', '-t', '4000', '--seed', '1'], model: 'tree.gltf',
      bake: ['-r', 'displaced-mesh'], export: [], first_camera_only: true },
    { name: 'enhanced-billboards', model: 'data/bunny.ply', bake: ['-r', 'enhanced-billboards'], export: [] },
    // alpha-masked leaf cards: one texel wide or less at 512 texels, which the viewer's walk must keep
    // as standin's does, leaf contours clipped to the edge lines the texels hold (0.9979; at 1024
    // texels 0.9977 / 0.9973, and 0.981 / 0.979 drawing those texels whole). The default's 2048 (the
    // leaf texture's) takes the same code path for 16x the layers and made this case 290 s of CI's
    // 25 minutes (0.9987 / 0.9973 there); 1024 took 96 s, 512 takes 25 s. First camera only: the
    // second (0.9972 at 1024) took 23 s more (35 s in CI) through the same export and shader path
    { name: 'enhanced-billboards tree', generate: ['tree', '-t', '4000', '--seed', '1'], model: 'tree.gltf',
      bake: ['-r', 'enhanced-billboards', '--resolution', '512'], export: [], at_least_iou: 0.99,
      first_camera_only: true },
    // the finest baked level (7: 128^3) as a plain voxel-face mesh
    { name: 'microfacets', model: 'data/bunny.ply', bake: ['-r', 'microfacets'], export: [] },
    // foliage as one square per voxel in the leaf's plane, cut out by the captures' coverage (MASK);
    // against `standin render` of the package 0.9584 with these 256 px captures (which halve the
    // case's time), since the renderer walks fallback views where its blend abstains (it was 0.931
    // when that render had holes where its nearest views saw branches and inner leaves hidden;
    // docs/RESULTS.md "Fallback views where the blend abstains"), so the 0.95 target holds; the same
    // web picture must also reach 0.95 against `standin render` of the model (0.971; "Microfacets
    // planes against the model"). First camera only (the second adds 20 s of CI time for the same
    // export path)
    { name: 'microfacets tree', generate: ['tree', '-t', '4000', '--seed', '1'], model: 'tree.gltf',
      bake: ['-r', 'microfacets', '--resolution', '256'], export: [], min_iou: 0.95,
      model_min_iou: 0.95, first_camera_only: true },
];

function skip(message) {
    console.log(`SKIP: ${message}`);
    process.exit(k_skip);
}

function run(command, args, cwd = repo_dir) {
    const result = spawnSync(command, args, { cwd, encoding: 'utf8' });
    if (result.error) throw new Error(`${command}: ${result.error.message}`);
    return result;
}

function cli(args) {
    const prefix = (process.env.STANDIN_CLI_PREFIX || '').split(' ').filter(Boolean);
    const all = [...prefix, options.cli, ...args];
    const result = run(all[0], all.slice(1));
    if (result.status !== 0) throw new Error(`standin ${args.join(' ')}: exit ${result.status}: ${(result.stderr || '').trim()}`);
    return result;
}

// the prerequisites: Chromium, and node_modules (npm ci when npm is there)
if (!existsSync(options.chromium)) skip(`no Chromium at ${options.chromium} (Debian package chromium; scripts/setup installs it)`);
if (['playwright-core', 'three', 'ktx2-encoder'].some((m) => !existsSync(join(web_dir, 'node_modules', m)))) {
    const npm = run('sh', ['-c', 'command -v npm']);
    if (npm.status !== 0) skip('npm is not installed: cannot install playwright-core and three (examples/web/package.json)');
    console.log('silhouette: npm ci in examples/web');
    const ci = run('npm', ['ci', '--no-audit', '--no-fund'], web_dir);
    if (ci.status !== 0) {
        console.error(`silhouette: npm ci failed in ${web_dir}:\n${ci.stdout}${ci.stderr}`);
        process.exit(1);
    }
}
if (!existsSync(options.cli)) {
    console.error(`silhouette: no standin executable at ${options.cli} (--cli)`);
    process.exit(2);
}

const { chromium } = await import(join(web_dir, 'node_modules', 'playwright-core', 'index.mjs'));
const { serve } = await import(join(web_dir, 'server.mjs'));

const started = Date.now();
rmSync(options.work, { recursive: true, force: true });
mkdirSync(options.work, { recursive: true });
const has_export = /^\s+export\b/m.test(run(options.cli, ['--help']).stdout || '');

const server = await serve([['/', web_dir], ['/repo', repo_dir], ['/work', options.work]]);
const base = `http://127.0.0.1:${server.address().port}`;
// WebGL2 without a GPU: ANGLE on SwiftShader (Chromium's own software Vulkan), deterministic
const browser = await chromium.launch({
    executablePath: options.chromium,
    headless: true,
    args: ['--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-sandbox'],
});

const camera_args = (c) => ['--azimuth', String(c.azimuth), '--elevation', String(c.elevation),
    '--distance', String(c.distance), '--fov', String(c.fov), '--size', k_size];
const camera_query = (c) => `azimuth=${c.azimuth}&elevation=${c.elevation}&distance=${c.distance}` +
    `&fov=${c.fov}&size=${k_size}&still=1`;

async function view_in_browser(query, truth_png, screenshot, model_png = null) {
    const [w, h] = k_size.split('x').map(Number);
    const page = await browser.newPage({ viewport: { width: w, height: h } });
    const messages = [];
    page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') messages.push(m.text()); });
    page.on('pageerror', (e) => messages.push(String(e)));
    try {
        await page.goto(`${base}/index.html?${query}`);
        await page.waitForFunction(() => window.standin && (window.standin.ready || window.standin.error), null, { timeout: 240000 });
        const state = await page.evaluate(() => ({ error: window.standin.error, info: window.standin.info }));
        if (state.error) throw new Error(`viewer: ${state.error}`);
        // (a frame of the tree's 35 billboard boxes takes ~13 s on SwiftShader on a loaded 2-core machine)
        await page.locator('#view').screenshot({ path: screenshot, omitBackground: true, timeout: 120000 });
        const iou = await page.evaluate((url) => window.standin.silhouette_iou(url), truth_png);
        // the same picture against a second truth (the model's own render), no second drawing
        const model = model_png ? await page.evaluate((url) => window.standin.silhouette_iou(url), model_png) : null;
        return { ...iou, info: state.info, model };
    } catch (error) {
        throw new Error(`${error.message}${messages.length ? `\n  browser: ${messages.join('\n  browser: ')}` : ''}`);
    } finally {
        await page.close();
    }
}

const results = [];
let failed = false;
try {
    for (const c of k_cases) {
        if (options.only && !c.name.includes(options.only)) continue;
        const slug = c.name.replace(/[^a-z0-9]+/gi, '_');
        // a generated model lies in the work folder (served as /work), a bundled one in the repository
        const model_path = c.generate ? join(options.work, c.model) : join(repo_dir, c.model);
        const model_url = c.generate ? `/work/${c.model}` : `/repo/${c.model}`;
        if (c.generate) cli(['generate', ...c.generate, '-o', model_path]);
        let pkg = null;
        let prepared = false;
        for (const [k, camera] of k_cameras.entries()) {
            if (camera.standins_only && !c.bake) continue;
            if (k > 0 && c.first_camera_only) continue;
            const t0 = Date.now();
            const view = `${slug}.az${camera.azimuth}_el${camera.elevation}`;
            const row = { name: c.name, camera };
            try {
                let query;
                const truth = join(options.work, `${view}.standin.png`);
                if (!c.bake) {
                    cli(['render', model_path, '-o', truth, ...camera_args(camera)]);
                    query = `model=${model_url}&view=model&${camera_query(camera)}`;
                } else {
                    if (!has_export) {
                        row.status = 'not run: this standin has no export command';
                        results.push(row);
                        console.log(`${row.status} ${c.name}`);
                        break;
                    }
                    pkg = join(options.work, `${slug}.standin`);
                    if (!prepared) {
                        cli(['bake', model_path, '-o', pkg, ...c.bake]);
                        cli(['export', pkg, '-o', join(options.work, `${slug}.glb`), ...c.export]);
                        prepared = true;
                    }
                    cli(['render', pkg, '-o', truth, ...camera_args(camera)]);
                    // framed by the model's box, as standin render frames a package by its source's bounds
                    query = `model=${model_url}&standin=/work/${slug}.glb&view=standin&${camera_query(camera)}`;
                }
                let model_png = null;
                if (c.model_min_iou) {
                    cli(['render', model_path, '-o', join(options.work, `${view}.model.png`), ...camera_args(camera)]);
                    model_png = `/work/${view}.model.png`;
                }
                const r = await view_in_browser(query, `/work/${view}.standin.png`, join(options.work, `${view}.web.png`), model_png);
                Object.assign(row, { iou: r.iou, web_pixels: r.web_pixels, standin_pixels: r.standin_pixels, info: r.info });
                // a case may hold a lower floor (min_iou), or a higher one where the viewer is known to
                // match standin closely (at_least_iou), so that losing that shows
                const floor = Math.max(Math.min(c.min_iou ?? 1, options.min_iou), c.at_least_iou ?? 0);
                row.status = r.iou >= floor ? 'pass' : 'FAIL';
                if (r.model) {
                    row.model_iou = r.model.iou;
                    row.model_pixels = r.model.standin_pixels;
                    if (r.model.iou < Math.min(c.model_min_iou, options.min_iou)) row.status = 'FAIL';
                }
                if (c.proxy && r.info.impostor_proxy !== c.proxy) {
                    row.status = 'FAIL';
                    row.error = `the impostor was drawn on the ${r.info.impostor_proxy}, not the ${c.proxy}`;
                }
                if (row.status !== 'pass') failed = true;
                if (c.ktx2 && k === 0) {
                    // the same export with its colour atlas as KTX2, against the same render
                    const t1 = Date.now();
                    const glb = join(options.work, `${slug}.glb`), ktx2_glb = join(options.work, `${slug}.ktx2.glb`);
                    const tool = run(process.execPath, [join(web_dir, 'tools', 'ktx2.mjs'), glb, ktx2_glb, ...c.ktx2]);
                    if (tool.status !== 0) throw new Error(`tools/ktx2.mjs: exit ${tool.status}: ${(tool.stderr || '').trim()}`);
                    const k2 = await view_in_browser(query.replace(`/work/${slug}.glb`, `/work/${slug}.ktx2.glb`),
                        `/work/${view}.standin.png`, join(options.work, `${view}.ktx2.web.png`));
                    row.ktx2 = { iou: k2.iou, web_pixels: k2.web_pixels, bytes_png: statSync(glb).size,
                        bytes_ktx2: statSync(ktx2_glb).size, color_texture: k2.info.color_texture, seconds: (Date.now() - t1) / 1000 };
                    // the viewer must have drawn the transcoded KTX2, not an image
                    const used_ktx2 = /^ktx2/.test(k2.info.color_texture || '');
                    if (k2.iou < options.min_iou || !used_ktx2) {
                        row.status = 'FAIL';
                        failed = true;
                    }
                }
            } catch (error) {
                row.status = 'FAIL';
                row.error = error.message;
                failed = true;
            }
            row.seconds = (Date.now() - t0) / 1000;
            results.push(row);
            const iou = row.iou !== undefined ? `IoU ${row.iou.toFixed(4)} (${row.web_pixels} web / ${row.standin_pixels} standin pixels)` : '';
            console.log(`${row.status.padEnd(5)} ${c.name}, azimuth ${camera.azimuth} elevation ${camera.elevation}: ${iou} ${row.seconds.toFixed(1)} s${row.error ? `\n  ${row.error}` : ''}`);
            if (row.model_iou !== undefined)
                console.log(`      ${c.name} against the model: IoU ${row.model_iou.toFixed(4)} (${row.model_pixels} model pixels)`);
            if (row.ktx2)
                console.log(`      ${c.name} as KTX2 (${row.ktx2.color_texture}; ${row.ktx2.bytes_png} -> ${row.ktx2.bytes_ktx2} bytes): ` +
                    `IoU ${row.ktx2.iou.toFixed(4)} (${row.ktx2.web_pixels} web pixels) ${row.ktx2.seconds.toFixed(1)} s`);
            if (row.error && !prepared && c.bake) break; // bake or export failed: no other camera can run
        }
    }
} finally {
    await browser.close();
    server.close();
}
const summary = { size: k_size, min_iou: options.min_iou, seconds: (Date.now() - started) / 1000, results };
writeFileSync(join(options.work, 'silhouette.json'), JSON.stringify(summary, null, 2) + '\n');
console.log(`silhouette: ${failed ? 'FAILED' : 'passed'} in ${summary.seconds.toFixed(1)} s (pictures and silhouette.json in ${options.work})`);
process.exit(failed ? 1 : 0);
