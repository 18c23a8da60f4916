#!/usr/bin/env bash
# A local stack of OGC services over a demo city folder, on loopback only (docs/services.md).
#
#   tools/services.sh up DIR [PORT]     start serving DIR (default port: a free one); prints the URLs
#   tools/services.sh down DIR          stop what `up DIR` started
#   tools/services.sh status DIR        the state folder and whether lighttpd runs
#
# DIR is a folder written by `histoview demo` (dtm.tif; buildings.geojson or buildings.gpkg;
# cameras.json). lighttpd listens on 127.0.0.1:PORT and runs MapServer's `mapserv` as a FastCGI
# program with a mapfile generated for DIR:
#   WCS 1.0 / 2.0 and WMS   the DTM, layer (coverage) "dtm" (float32 GeoTIFF; ESRI ASCII grid with
#                           FORMAT=text/plain, for the browser page)
#   WFS 2.0                 the footprints, type name "buildings" (GML or GeoJSON)
#   OGC API - Features      the footprints, collection "buildings"
#   WFS 2.0                 the photographs' cameras, type name "cameras", when DIR has
#                           cameras.gpkg (histoview cameras export --ogr; docs/formats.md)
#   static files            DIR itself under /files/ (cameras.json, the photographs, a web export
#                           and its page)
#   IIIF Image API 2        the tiled pyramidal TIFFs of DIR/iiif/ under /iiif?IIIF=NAME.tif/...
#                           (iipsrv, Debian's iipimage-server, through FastCGI), when DIR has
#                           an iiif/ folder and iipsrv is installed
#   WMTS                    the orthophoto, layer "orthophoto", by MapCache under /mapcache/wmts,
#                           when DIR has orthophoto.tif and mapcache-cgi is installed
#   WMTS                    the DTM, layer "dtm", float32 GeoTIFF tiles from MapServer's WMS, by
#                           MapCache under /elevation/wmts, when mapcache-cgi is installed
# Every response carries Access-Control-Allow-Origin: *. Everything runs as the invoking user; the
# configuration, logs and pidfile live in a private temporary folder (printed by `up`), never in DIR.
set -euo pipefail

usage() { sed -n '3,6p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
die() { echo "services.sh: $*" >&2; exit 1; }

cmd=${1:-}
[[ $cmd == up || $cmd == down || $cmd == status ]] || usage
DIR=${2:-}
[[ -n $DIR ]] || usage
[[ -d $DIR ]] || die "$DIR: not a folder"
DIR=$(cd "$DIR" && pwd -P)

# One state folder per served folder and user, so that `down DIR` finds what `up DIR` started.
key=$(printf '%s' "$DIR" | md5sum | cut -c1-12)
STATE=${TMPDIR:-/tmp}/histoview-services-$(id -u)-$key

lighttpd_pid() {
  [[ -s $STATE/lighttpd.pid ]] || return 1
  local pid
  pid=$(cat "$STATE/lighttpd.pid")
  [[ $pid =~ ^[0-9]+$ ]] && kill -0 "$pid" 2>/dev/null && echo "$pid"
}

stop() {
  local pid
  if pid=$(lighttpd_pid); then
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then kill -9 "$pid" 2>/dev/null || true; fi
    echo "stopped lighttpd ($pid) serving $DIR"
  fi
  rm -f "$STATE/lighttpd.pid"
}

case $cmd in
  down)
    if [[ -d $STATE ]]; then stop; rm -rf "$STATE"; else echo "nothing runs for $DIR"; fi
    exit 0
    ;;
  status)
    if pid=$(lighttpd_pid); then echo "running: lighttpd $pid, $(cat "$STATE/url"), state $STATE"
    else echo "not running ($DIR)"; exit 1; fi
    exit 0
    ;;
esac

# --- up
for tool in lighttpd python3; do
  command -v "$tool" >/dev/null || die "$tool not found (tools/install-deps.sh installs it)"
done
MAPSERV=${HV_MAPSERV:-/usr/lib/cgi-bin/mapserv}
[[ -x $MAPSERV ]] || die "$MAPSERV not found (package cgi-mapserver; tools/install-deps.sh installs it)"

[[ -f $DIR/dtm.tif ]] || die "$DIR/dtm.tif: not found (expected a folder written by histoview demo)"
footprints=
for f in buildings.gpkg buildings.geojson; do [[ -f $DIR/$f ]] && footprints=$DIR/$f && break; done
[[ -n $footprints ]] || die "$DIR: neither buildings.gpkg nor buildings.geojson found"

# The cameras as a point layer (docs/formats.md, "Cameras as an OGR point layer"), when written:
# 3D points ("point25d": MapServer writes the height only when told), 10 decimals.
cameras_layer=
if [[ -f $DIR/cameras.gpkg ]]; then
  cameras_layer=$(cat <<EOF
  LAYER
    NAME "cameras"
    TYPE POINT
    STATUS ON
    CONNECTIONTYPE OGR
    CONNECTION "$DIR/cameras.gpkg"
    DATA "cameras"
    PROJECTION "init=epsg:2154" END
    TEMPLATE "void"
    METADATA
      "wfs_title" "cameras"
      "wfs_srs" "EPSG:2154 EPSG:4326"
      "wfs_enable_request" "*"
      "gml_include_items" "all"
      "gml_types" "auto"
      "gml_geomtype" "point25d"
      "wfs_geometry_precision" "10"
      "oga_enable_request" "*"
      "ows_enable_request" "*"
    END
  END
EOF
)
fi

if lighttpd_pid >/dev/null; then die "already serving $DIR: $(cat "$STATE/url") (tools/services.sh down $DIR)"; fi

PORT=${3:-}
if [[ -z $PORT ]]; then
  PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
fi
[[ $PORT =~ ^[0-9]+$ ]] && ((PORT > 0 && PORT < 65536)) || die "port: expected a number in 1..65535, got '$PORT'"

rm -rf "$STATE"
mkdir -m 700 "$STATE"
URL=http://127.0.0.1:$PORT

# A GeoTIFF's grid and no-data value (the DTM's for the WCS metadata, the orthophoto's for
# MapCache's grid): read from its tags (ModelPixelScale, ModelTiepoint, GDAL_NODATA) by a few lines
# of Python, so no GDAL tool is needed.
tiff_grid() {
  python3 - "$1" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
order = {b"II": "<", b"MM": ">"}[data[:2]]
magic = struct.unpack(order + "H", data[2:4])[0]
big = magic == 43
if big:
    ifd = struct.unpack(order + "Q", data[8:16])[0]
    count = struct.unpack(order + "Q", data[ifd:ifd + 8])[0]; at = ifd + 8; size = 20
else:
    ifd = struct.unpack(order + "I", data[4:8])[0]
    count = struct.unpack(order + "H", data[ifd:ifd + 2])[0]; at = ifd + 2; size = 12
kinds = {1: "B", 2: "s", 3: "H", 4: "I", 12: "d", 16: "Q"}
tags = {}
for i in range(count):
    e = data[at + i * size: at + (i + 1) * size]
    tag, kind = struct.unpack(order + "HH", e[:4])
    n = struct.unpack(order + ("Q" if big else "I"), e[4:12] if big else e[4:8])[0]
    fmt = kinds.get(kind)
    if fmt is None: continue
    nbytes = struct.calcsize(fmt) * n
    inline = e[12:20] if big else e[8:12]
    raw = inline[:nbytes] if nbytes <= len(inline) else data[struct.unpack(order + ("Q" if big else "I"), inline)[0]:][:nbytes]
    tags[tag] = raw.rstrip(b"\0").decode() if fmt == "s" else struct.unpack(order + fmt * n, raw)
w, h = tags[256][0], tags[257][0]
sx, sy = tags[33550][:2]
tie = tags[33922]
x0 = tie[3] - tie[0] * sx; y1 = tie[4] + tie[1] * sy
print(w, h, x0, y1 - h * sy, x0 + w * sx, y1, sx, sy, tags.get(42113, "").strip() or "none")
PY
}
read -r cols rows minx miny maxx maxy resx resy nodata < <(tiff_grid "$DIR/dtm.tif")
[[ -n ${resy:-} ]] || die "$DIR/dtm.tif: cannot read its size and georeferencing"
[[ $nodata == none ]] && nodata=

cat >"$STATE/city.map" <<EOF
MAP
  NAME "city"
  EXTENT $minx $miny $maxx $maxy
  SIZE $cols $rows
  UNITS METERS
  PROJECTION "init=epsg:2154" END
  OUTPUTFORMAT
    NAME "GTiff32"
    DRIVER "GDAL/GTiff"
    MIMETYPE "image/tiff"
    IMAGEMODE FLOAT32
    EXTENSION "tif"
  END
  OUTPUTFORMAT
    NAME "AAIGrid"
    DRIVER "GDAL/AAIGrid"
    MIMETYPE "text/plain"
    IMAGEMODE FLOAT32
    EXTENSION "asc"
    FORMATOPTION "SIGNIFICANT_DIGITS=9"
  END
  WEB
    METADATA
      "ows_title" "histoview demo city"
      "ows_onlineresource" "$URL/mapserv?"
      "ows_srs" "EPSG:2154 EPSG:4326"
      "ows_enable_request" "*"
      "oga_onlineresource" "$URL/mapserv/city/ogcapi"
      "oga_html_template_directory" "/usr/share/mapserver/ogcapi/templates/html-plain/"
      "wfs_getfeature_formatlist" "geojson"
      "wfs_maxfeatures" "100000"
    END
  END
  OUTPUTFORMAT
    NAME "geojson"
    DRIVER "OGR/GEOJSON"
    MIMETYPE "application/json; subtype=geojson"
    FORMATOPTION "STORAGE=stream"
    FORMATOPTION "FORM=SIMPLE"
    FORMATOPTION "LCO:COORDINATE_PRECISION=6"
  END
  LAYER
    NAME "dtm"
    TYPE RASTER
    STATUS ON
    DATA "$DIR/dtm.tif"
    PROJECTION "init=epsg:2154" END
    PROCESSING "RESAMPLE=NEAREST"
    METADATA
      "wcs_label" "dtm"
      "wcs_rangeset_name" "elevation"
      "wcs_rangeset_label" "elevation (m)"
      "wcs_formats" "GTiff32 AAIGrid"
      "wcs_nativeformat" "GTiff32"
      "wcs_bandcount" "1"
      "wcs_imagemode" "FLOAT32"
      "wcs_srs" "EPSG:2154"
      "wcs_native_crs" "EPSG:2154"
      "wcs_extent" "$minx $miny $maxx $maxy"
      "wcs_resolution" "$resx $resy"
      "wcs_size" "$cols $rows"
      ${nodata:+\"wcs_rangeset_nullvalue\" \"$nodata\"}
      "ows_enable_request" "*"
    END
  END
  LAYER
    NAME "buildings"
    TYPE POLYGON
    STATUS ON
    CONNECTIONTYPE OGR
    CONNECTION "$footprints"
    PROJECTION "init=epsg:2154" END
    TEMPLATE "void"
    METADATA
      "wfs_title" "buildings"
      "wfs_srs" "EPSG:2154 EPSG:4326"
      "wfs_extent" "$minx $miny $maxx $maxy"
      "wfs_enable_request" "*"
      "gml_include_items" "all"
      "gml_types" "auto"
      "gml_featureid" "id"
      "oga_enable_request" "*"
      "oga_geometry_precision" "9"
      "ows_enable_request" "*"
    END
    CLASS STYLE COLOR 180 160 140 OUTLINECOLOR 60 60 60 END END
  END
$cameras_layer
END
EOF

cat >"$STATE/mapserver.conf" <<EOF
CONFIG
  ENV
    MS_MAPFILE "$STATE/city.map"
    MS_ERRORFILE "$STATE/mapserver.log"
  END
  MAPS
    "city" "$STATE/city.map"
  END
END
EOF

# IIIF: iipsrv as a FastCGI program lighttpd starts (one process, on a socket in the state folder).
IIPSRV=${HV_IIPSRV:-/usr/lib/iipimage-server/iipsrv.fcgi}
iiif_conf=
if [[ -d $DIR/iiif && -x $IIPSRV ]]; then
  iiif_conf=$(cat <<IIIF
fastcgi.server += ("/iiif" => ((
  "socket" => "$STATE/iipsrv.sock", "bin-path" => "$IIPSRV", "check-local" => "disable", "max-procs" => 1,
  "bin-environment" => ("FILESYSTEM_PREFIX" => "$DIR/iiif/", "LOGFILE" => "$STATE/iipsrv.log", "VERBOSITY" => "1",
                        "MAX_CVT" => "4096", "JPEG_QUALITY" => "90")
)))
IIIF
)
elif [[ -d $DIR/iiif ]]; then
  echo "services.sh: $IIPSRV not found: no IIIF service (package iipimage-server)" >&2
fi

# WMTS by MapCache (Debian's mapcache-cgi) as a CGI program, tiles cached under the state folder;
# one configuration (and URL) per layer, so that each WMTS has the one layer GDAL opens unasked.
#   /mapcache   the orthophoto (DIR/orthophoto.tif, written by histoview demo): MapCache's GDAL
#               source reading the file, PNG tiles. One grid in EPSG:2154 over the orthophoto's own
#               extent, its top-left corner that of the file and its finest level the file's own
#               pixel, so a tile's pixels are the file's pixels; two coarser levels for GDAL's
#               overview choice.
#   /elevation  the DTM as float32 GeoTIFF tiles: MapCache's WMS source asks MapServer's WMS (layer
#               dtm, FORMAT=image/tiff: the GTiff32 output format, nearest sampling) and its RAW
#               format keeps MapServer's answer byte for byte (MapCache's image formats are 8-bit).
#               The grid is the DTM's own (top-left corner, cell size; two coarser levels), so a
#               tile's cells are the file's cells.
MAPCACHE=${HV_MAPCACHE:-/usr/lib/cgi-bin/mapcache}
mapcache_conf=
mapcache_ortho=
# mapcache_xml NAME GRID_EXTENT RESOLUTION SOURCE_XML FORMAT_XML FORMAT: a configuration of one
# tileset NAME over one grid, written to $STATE/mapcache-NAME.xml.
mapcache_xml() {
  cat >"$STATE/mapcache-$1.xml" <<EOF
<?xml version="1.0" encoding="UTF-8"?>
<mapcache>
  <cache name="disk" type="disk"><base>$STATE/mapcache-tiles</base></cache>
  $4
  <grid name="$1">
    <metadata><title>EPSG:2154 over the $1</title></metadata>
    <srs>EPSG:2154</srs>
    <size>256 256</size>
    <extent>$2</extent>
    <origin>top-left</origin>
    <units>m</units>
    <resolutions>$(python3 -c "import sys; r = float(sys.argv[1]); print(repr(r * 4), repr(r * 2), repr(r))" "$3")</resolutions>
  </grid>
  $5
  <tileset name="$1">
    <source>$1</source><cache>disk</cache><grid>$1</grid><format>$6</format>
    <metatile>1 1</metatile><metabuffer>0</metabuffer>
  </tileset>
  <service type="wmts" enabled="true"/>
  <service type="wms" enabled="false"/>
  <errors>report</errors>
  <lock_dir>$STATE/mapcache-lock</lock_dir>
  <threaded_fetching>false</threaded_fetching>
</mapcache>
EOF
}
if [[ -x $MAPCACHE ]]; then
  mkdir -p "$STATE/mapcache-tiles" "$STATE/mapcache-lock"
  if [[ -f $DIR/orthophoto.tif ]]; then
    read -r _ _ ominx ominy omaxx omaxy ores _ _ < <(tiff_grid "$DIR/orthophoto.tif") ||
      die "$DIR/orthophoto.tif: cannot read its size and georeferencing"
    mapcache_ortho=1
    mapcache_xml orthophoto "$ominx $ominy $omaxx $omaxy" "$ores" \
      "<source name=\"orthophoto\" type=\"gdal\"><data>$DIR/orthophoto.tif</data></source>" \
      '<format name="PNG32" type="PNG"><compression>fast</compression></format>' PNG32
  fi
  mapcache_xml dtm "$minx $miny $maxx $maxy" "$resx" \
    "<source name=\"dtm\" type=\"wms\"><getmap><params><FORMAT>image/tiff</FORMAT><LAYERS>dtm</LAYERS></params></getmap><http><url>$URL/mapserv?map=city</url></http></source>" \
    '<format name="float32" type="RAW"><extension>tif</extension><mime_type>image/tiff</mime_type></format>' float32
  # mapcache_cgi PREFIX NAME: lighttpd runs MapCache under PREFIX with mapcache-NAME.xml.
  mapcache_cgi() {
    cat <<MC
alias.url += ("/$1" => "$MAPCACHE")
\$HTTP["url"] =~ "^/$1/" {
  cgi.assign = ("" => "")
  setenv.add-environment = ("MAPCACHE_CONFIG_FILE" => "$STATE/mapcache-$2.xml")
}
MC
  }
  mapcache_conf=$(mapcache_cgi elevation dtm)
  if [[ -n $mapcache_ortho ]]; then mapcache_conf+=$'\n'$(mapcache_cgi mapcache orthophoto); fi
else
  echo "services.sh: $MAPCACHE not found: no WMTS of the orthophoto and the DTM (package mapcache-cgi)" >&2
fi

cat >"$STATE/lighttpd.conf" <<EOF
server.bind = "127.0.0.1"
server.port = $PORT
server.document-root = "$STATE/www"
server.pid-file = "$STATE/lighttpd.pid"
server.errorlog = "$STATE/error.log"
server.modules = ("mod_alias", "mod_setenv", "mod_cgi", "mod_fastcgi", "mod_accesslog")
accesslog.filename = "$STATE/access.log"
server.max-worker = 0
mimetype.assign = (".json" => "application/json", ".png" => "image/png", ".jpg" => "image/jpeg",
                   ".tif" => "image/tiff", ".geojson" => "application/geo+json",
                   ".html" => "text/html", ".js" => "text/javascript", ".css" => "text/css",
                   ".wasm" => "application/wasm", "" => "application/octet-stream")
alias.url = ("/files/" => "$DIR/")
# MapServer as a FastCGI program (two processes that stay up): a CGI program would start, read its
# configuration and open the data anew on every request, about 0.1 s each on a quiet machine and a
# second on a loaded one, and a tile of an OGC API layer takes one request per page.
fastcgi.server = ("/mapserv" => ((
  "socket" => "$STATE/mapserv.sock", "bin-path" => "$MAPSERV", "check-local" => "disable", "max-procs" => 2,
  "bin-environment" => ("MAPSERVER_CONFIG_FILE" => "$STATE/mapserver.conf")
)))
setenv.add-response-header = ("Access-Control-Allow-Origin" => "*")
$iiif_conf
$mapcache_conf
EOF
mkdir -p "$STATE/www"
echo "$URL" >"$STATE/url"

lighttpd -tt -f "$STATE/lighttpd.conf" >/dev/null || die "lighttpd refused $STATE/lighttpd.conf"
lighttpd -f "$STATE/lighttpd.conf" || die "lighttpd did not start (port $PORT taken?); see $STATE/error.log"
ok=0
for _ in $(seq 50); do
  if python3 - "$PORT" <<'PY' 2>/dev/null; then ok=1; break; fi
import socket, sys
socket.create_connection(("127.0.0.1", int(sys.argv[1])), timeout=0.2).close()
PY
  sleep 0.1
done
((ok)) || { stop; die "lighttpd does not answer on 127.0.0.1:$PORT; see $STATE/error.log"; }

cat <<EOF
serving $DIR on $URL (state: $STATE)
  WCS terrain:    WCS:$URL/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm
  WMS:            $URL/mapserv?map=city&SERVICE=WMS&REQUEST=GetCapabilities
  WFS buildings:  WFS:$URL/mapserv?map=city&TYPENAME=ms:buildings
  OGC API:        OAPIF:$URL/mapserv/city/ogcapi/collections/buildings
${cameras_layer:+  WFS cameras:    WFS:$URL/mapserv?map=city&TYPENAME=ms:cameras
}${iiif_conf:+  IIIF:           $URL/iiif?IIIF=NAME.tif/info.json (NAME.tif in $DIR/iiif/)
}${mapcache_ortho:+  WMTS orthophoto: WMTS:$URL/mapcache/wmts?SERVICE=WMTS&REQUEST=GetCapabilities
}${mapcache_conf:+  WMTS elevation: $URL/elevation/wmts?SERVICE=WMTS&REQUEST=GetCapabilities (float32 tiles: a GDAL_WMTS description says so, docs/services.md)
}  files:          $URL/files/cameras.json
stop with: tools/services.sh down $DIR
EOF
