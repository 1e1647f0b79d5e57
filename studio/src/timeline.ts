// The timeline: frame slider, frame field, range and rate (kept in the network), play and stop. Playing shows every frame in turn, advancing when the previous frame's cook arrived and not faster than the network's fps.

import type { AppStore } from './store';

export class Timeline {
  playing = false;
  /** One entry per frame shown while playing: how many nodes cooked and came from the cache. */
  readonly playLog: { frame: number; hits: number; misses: number; at: number }[] = [];
  private slider: HTMLInputElement;
  private field: HTMLInputElement;
  private start: HTMLInputElement;
  private end: HTMLInputElement;
  private play: HTMLButtonElement;
  private rate: HTMLInputElement;
  private ticks: HTMLElement;
  private ticksShown = '';
  /** When the frame shown last was asked for (playback paces from it). */
  private steppedAt = 0;
  private pending = 0;
  /** The frame playback asked for last. */
  private asked: number | null = null;

  constructor(
    host: HTMLElement,
    private store: AppStore,
    private setFrame: (f: number) => void,
    setTimeline: (frames: [number, number], fps: number) => void,
  ) {
    host.innerHTML = `<button class="play" title="Play / stop (loops the range)">▶</button>
      <input class="start" type="number" title="First frame"> <span class="slider-wrap"><input class="slider" type="range" step="1"><span class="ticks"></span></span>
      <input class="end" type="number" title="Last frame"> <label>Frame <input class="frame" type="number" step="1"></label>
      <label>FPS <input class="fps" type="number" min="1" step="1" title="Playback rate, kept in the network"></label>`;
    this.play = host.querySelector('.play')!;
    this.slider = host.querySelector('.slider')!;
    this.field = host.querySelector('.frame')!;
    this.start = host.querySelector('.start')!;
    this.end = host.querySelector('.end')!;
    this.rate = host.querySelector('.fps')!;
    this.ticks = host.querySelector('.ticks')!;
    this.slider.addEventListener('input', () => this.setFrame(Number(this.slider.value)));
    this.field.addEventListener('change', () => this.setFrame(Number(this.field.value)));
    const range = () => {
      const a = Math.round(Number(this.start.value));
      const b = Math.round(Number(this.end.value));
      const fps = Number(this.rate.value);
      if (Number.isFinite(a) && Number.isFinite(b) && b >= a && fps > 0) {
        store.range = [a, b];
        store.rangeSet = true;
        store.fps = fps;
        setTimeline([a, b], fps);
      }
      this.render();
    };
    this.start.addEventListener('change', range);
    this.end.addEventListener('change', range);
    this.rate.addEventListener('change', range);
    this.play.addEventListener('click', () => this.toggle());
  }

  toggle() {
    this.playing = !this.playing;
    this.play.textContent = this.playing ? '■' : '▶';
    clearTimeout(this.pending);
    this.asked = null;
    if (this.playing) this.step();
  }

  /** Called when a cook for the shown frame arrived: log it and go to the next frame, one frame time after the last. */
  cooked(frame: number, hits: number, misses: number) {
    // Only the frame playback asked for advances it (an edit's recook may land in between).
    if (!this.playing || frame !== this.asked) return;
    this.playLog.push({ frame, hits, misses, at: performance.now() });
    const wait = this.steppedAt + 1000 / this.store.fps - performance.now();
    clearTimeout(this.pending);
    if (wait > 1) this.pending = window.setTimeout(() => this.playing && this.step(), wait);
    else this.step();
  }

  private step() {
    const [a, b] = this.store.range;
    const f = this.asked ?? this.store.state?.view.frame ?? a;
    this.steppedAt = performance.now();
    this.asked = f >= b || f < a ? a : f + 1;
    this.setFrame(this.asked);
  }

  /** Draws the frame controls, and a tick over the slider at each of `keys` (the selected node's key frames). */
  render(keys: number[] = []) {
    const [a, b] = this.store.range;
    const shown = `${a}|${b}|${keys.join()}`;
    if (shown !== this.ticksShown) {
      this.ticksShown = shown;
      this.ticks.replaceChildren(
        ...keys
          .filter((k) => k >= a && k <= b)
          .map((k) => {
            const t = document.createElement('i');
            // The slider's thumb is 16 px wide: its centre runs from 8 px to the width less 8 px.
            t.style.left = `calc(8px + (100% - 16px) * ${b > a ? (k - a) / (b - a) : 0})`;
            t.title = `key at frame ${k}`;
            t.dataset.frame = String(k);
            return t;
          }),
      );
    }
    const f = this.store.state?.view.frame ?? 1;
    this.slider.min = String(a);
    this.slider.max = String(b);
    if (document.activeElement !== this.slider) this.slider.value = String(f);
    if (document.activeElement !== this.field) this.field.value = String(f);
    if (document.activeElement !== this.start) this.start.value = String(a);
    if (document.activeElement !== this.end) this.end.value = String(b);
    if (document.activeElement !== this.rate) this.rate.value = String(this.store.fps);
  }
}
