#!/usr/bin/env bash
# Opens the dialog of one of treeskel's filters in a running MeshLab 2020.09 GUI, by clicking
# Filters > Point Set > the filter with xdotool, and waits until the dialog is there.
# For the screenshots and the GUI tests: MeshLab in a 1280x1024 Xvfb screen, where its main window
# opens at the top left. Usage (DISPLAY set): gui-open-filter.sh "Tree Mesh from Point Cloud"
# Prints where the dialog's buttons are: "APPLY_X APPLY_Y CLOSE_X CLOSE_Y".
set -euo pipefail
filter=${1:?usage: gui-open-filter.sh FILTER_NAME}
case $filter in
  "Tree Mesh from Point Cloud") row=686 ;;
  "Tree Skeleton (CPC)") row=711 ;;
  *) echo "gui-open-filter: unknown filter '$filter'" >&2; exit 2 ;;
esac
for i in $(seq 60); do xdotool search --onlyvisible --name "MeshLab 2020" >/dev/null 2>&1 && break; sleep 0.5; done
sleep 3                                        # let it finish loading the layer
pattern=$(printf '%s' "$filter" | sed 's/[][().*^$+?{}|\\]/\\&/g')
# On a loaded machine a menu can open later than the next click: then the menus are closed with
# Escape and the clicks tried again, three times in all.
for attempt in 1 2 3; do
  xdotool mousemove 120 10 click 1; sleep $attempt      # Filters
  xdotool mousemove 155 386 click 1; sleep $attempt     # Point Set
  xdotool mousemove 628 "$row" click 1
  for i in $(seq 20); do
    dialog=$(xdotool search --onlyvisible --name "^$pattern\$" 2>/dev/null | head -n 1) || true
    if [ -n "$dialog" ]; then
      sleep 1
      eval "$(xdotool getwindowgeometry --shell "$dialog")"   # X Y WIDTH HEIGHT
      # Close and Apply are the last row of buttons, left and right half, 20 pixels above the bottom.
      echo "$((X + WIDTH * 3 / 4)) $((Y + HEIGHT - 20)) $((X + WIDTH / 4)) $((Y + HEIGHT - 20))"
      exit 0
    fi
    sleep 0.5
  done
  xdotool key Escape; sleep 0.5; xdotool key Escape; sleep 0.5
done
echo "gui-open-filter: the dialog of '$filter' did not open" >&2
exit 1
