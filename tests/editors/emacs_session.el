;;; emacs_session.el --- Emacs's side of tests/editors/test_emacs.py  -*- lexical-binding: t -*-

;; Run in batch (`emacs --batch -q -l emacs_session.el`: Debian's site start loads eglot).
;; Reads its orders from the JSON file named by $SCRIPTC_EDITOR_TEST: opens the script in the
;; `scriptc-mode' of
;; docs/editors.md, connects eglot to `scriptc lsp', makes each edit as a person would
;; (delete, insert: eglot computes the protocol's ranges), then rewrites the configuration;
;; after the opening and after each step it waits until the diagnostics change and records
;; the buffer's lines and its diagnostics (columns in characters).  Writes the record to the
;; result file and exits (status 1 on an error).

(require 'eglot)  ; Debian's elpa-eglot on Emacs 28; Emacs 29 and newer carry it
(require 'json)

(define-derived-mode scriptc-mode prog-mode "scriptc"
  "Major mode for robot activity scripts (as docs/editors.md gives it)."
  (modify-syntax-entry ?% "!" scriptc-mode-syntax-table)
  (modify-syntax-entry ?\" "\"" scriptc-mode-syntax-table)
  (setq-local comment-start "% ")
  (setq-local comment-end " %")
  (setq-local indent-tabs-mode nil))

(defvar scriptc-test-setup
  (let ((json-object-type 'alist) (json-array-type 'list) (json-key-type 'symbol))
    (json-read-file (getenv "SCRIPTC_EDITOR_TEST"))))

(defun scriptc-test-get (key) (alist-get key scriptc-test-setup))

(defvar scriptc-test-record nil)

(defun scriptc-test-diagnostics ()
  "The buffer's diagnostics from the server, as eglot converted them to regions."
  (sort
   (mapcar (lambda (d)
             (let ((beg (flymake-diagnostic-beg d)) (end (flymake-diagnostic-end d)))
               (save-excursion
                 (list (cons 'text (flymake-diagnostic-text d))
                       (cons 'line (progn (goto-char beg) (1- (line-number-at-pos))))
                       (cons 'column (- beg (line-beginning-position)))
                       (cons 'end_line (progn (goto-char end) (1- (line-number-at-pos))))
                       (cons 'end_column (- end (line-beginning-position)))))))
           eglot--diagnostics)
   (lambda (a b)
     (or (< (alist-get 'line a) (alist-get 'line b))
         (and (= (alist-get 'line a) (alist-get 'line b))
              (< (alist-get 'column a) (alist-get 'column b)))))))

(defun scriptc-test-step (name act)
  (let ((before (scriptc-test-diagnostics))
        (deadline (+ (float-time) (/ (scriptc-test-get 'timeout_ms) 1000.0)))
        changed)
    (funcall act)
    (while (and (not changed) (< (float-time) deadline))
      (accept-process-output nil 0.05)
      (setq changed (not (equal (scriptc-test-diagnostics) before))))
    (push (list (cons 'name name) (cons 'changed (if changed t :json-false))
                (cons 'lines (split-string (buffer-substring-no-properties (point-min) (point-max))
                                           "\n"))
                (cons 'diagnostics (or (scriptc-test-diagnostics) [])))
          scriptc-test-record)))

(defun scriptc-test-run ()
  ;; Diagnostics are kept by eglot as they arrive (no Flymake timer to wait for in batch).
  (setq flymake-no-changes-timeout nil)
  (setq eglot-send-changes-idle-time 0.05)
  (add-to-list 'eglot-server-programs
               (cons 'scriptc-mode (scriptc-test-get 'cmd)))
  (find-file (scriptc-test-get 'file))
  (scriptc-mode)
  (apply #'eglot (eglot--guess-contact))
  (scriptc-test-step "open" #'ignore)
  (let ((n 0))
    (dolist (edit (scriptc-test-get 'edits))
      (setq n (1+ n))
      (scriptc-test-step
       (format "edit %d" n)
       (lambda ()
         (goto-char (point-min))
         (forward-line (alist-get 'line edit))
         (forward-char (alist-get 'start edit))
         (delete-char (- (alist-get 'end edit) (alist-get 'start edit)))
         (insert (alist-get 'new_text edit))
         ;; eglot sends the changes on an idle timer, and a batch Emacs is never idle:
         ;; send them as that timer would.
         (eglot--signal-textDocument/didChange)))))
  (scriptc-test-step
   "configuration"
   (lambda ()
     (with-temp-file (scriptc-test-get 'config) (insert (scriptc-test-get 'config_later))))))

(let ((status 0) error-text)
  (condition-case err
      (scriptc-test-run)
    (error (setq status 1 error-text (error-message-string err))))
  (let ((encoding (ignore-errors
                    (plist-get (eglot--capabilities (eglot-current-server)) :positionEncoding))))
    (with-temp-file (scriptc-test-get 'result)
      (insert (json-encode
               (append (list (cons 'steps (reverse scriptc-test-record))
                             (cons 'position_encoding encoding))
                       (and error-text (list (cons 'error error-text))))))))
  (ignore-errors (let ((eglot-autoshutdown t)) (eglot-shutdown (eglot-current-server))))
  (kill-emacs status))
